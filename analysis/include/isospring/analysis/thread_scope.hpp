#pragma once
// Sets the OpenMP thread count for a solve and restores the caller's on scope exit, so that a
// `threads` option of one solve does not leak into the rest of the program.
#include <omp.h>

namespace isospring::analysis {

class ThreadScope {
 public:
  /// threads <= 0 keeps the current count.
  explicit ThreadScope(int threads) : previous_(omp_get_max_threads()) {
    if (threads > 0) omp_set_num_threads(threads);
  }
  ~ThreadScope() { omp_set_num_threads(previous_); }
  ThreadScope(const ThreadScope&) = delete;
  ThreadScope& operator=(const ThreadScope&) = delete;

 private:
  int previous_;
};

}  // namespace isospring::analysis
