#pragma once
// Sets the thread count of a solve, OpenMP (CHOLMOD, Eigen) and OpenBLAS's own thread pool (the
// BLAS behind CHOLMOD's supernodes), and restores the caller's counts on scope exit, so that a
// `threads` option of one solve does not leak into the rest of the program.
//
// Why OpenBLAS too: Debian's pthread OpenBLAS keeps its own workers, which omp_set_num_threads
// does not reach; in identify's single-threaded loop they still split every dpotrf and spun in
// sched_yield between the calls (seen with gdb in a 3D run on a loaded 2-core machine).
namespace isospring::analysis {

class ThreadScope {
 public:
  /// threads <= 0 keeps the current counts.
  explicit ThreadScope(int threads);
  ~ThreadScope();
  ThreadScope(const ThreadScope&) = delete;
  ThreadScope& operator=(const ThreadScope&) = delete;

 private:
  int previous_openmp_;
  int previous_blas_;  // 0 when the loaded BLAS has no thread control (ATLAS, reference BLAS)
};

}  // namespace isospring::analysis
