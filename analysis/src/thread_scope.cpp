#include "isospring/analysis/thread_scope.hpp"

#include <dlfcn.h>
#include <omp.h>

namespace isospring::analysis {

namespace {

// OpenBLAS's thread controls, looked up at run time: the program links the generic
// libblas.so.3, which may be OpenBLAS, ATLAS or the reference BLAS (blas_runtime.hpp).
using GetThreads = int (*)();
using SetThreads = void (*)(int);

GetThreads openblas_get() {
  static const auto function =
      reinterpret_cast<GetThreads>(dlsym(RTLD_DEFAULT, "openblas_get_num_threads"));
  return function;
}

SetThreads openblas_set() {
  static const auto function =
      reinterpret_cast<SetThreads>(dlsym(RTLD_DEFAULT, "openblas_set_num_threads"));
  return function;
}

}  // namespace

ThreadScope::ThreadScope(int threads)
    : previous_openmp_(omp_get_max_threads()),
      previous_blas_(openblas_get() && openblas_set() ? openblas_get()() : 0) {
  if (threads <= 0) return;
  omp_set_num_threads(threads);
  if (previous_blas_ > 0) openblas_set()(threads);
}

ThreadScope::~ThreadScope() {
  omp_set_num_threads(previous_openmp_);
  if (previous_blas_ > 0) openblas_set()(previous_blas_);
}

}  // namespace isospring::analysis
