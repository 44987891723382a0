// ThreadScope sets OpenMP's and OpenBLAS's thread counts for a scope and restores both.
#include <dlfcn.h>
#include <gtest/gtest.h>
#include <omp.h>

#include "isospring/analysis/thread_scope.hpp"

namespace isospring::analysis {
namespace {

TEST(ThreadScope, SetsAndRestoresOpenMpAndOpenBlasThreads) {
  using GetThreads = int (*)();
  using SetThreads = void (*)(int);
  const auto blas_get =
      reinterpret_cast<GetThreads>(dlsym(RTLD_DEFAULT, "openblas_get_num_threads"));
  const auto blas_set =
      reinterpret_cast<SetThreads>(dlsym(RTLD_DEFAULT, "openblas_set_num_threads"));
  // Two threads outside, so that a scope of one is a visible change on any machine.
  omp_set_num_threads(2);
  if (blas_set) blas_set(2);
  {
    const ThreadScope scope(1);
    EXPECT_EQ(omp_get_max_threads(), 1);
    if (blas_get) {
      EXPECT_EQ(blas_get(), 1);
    }
    {
      const ThreadScope keep(0);  // <= 0 keeps the counts
      EXPECT_EQ(omp_get_max_threads(), 1);
    }
    EXPECT_EQ(omp_get_max_threads(), 1);
  }
  EXPECT_EQ(omp_get_max_threads(), 2);
  if (blas_get) {
    EXPECT_EQ(blas_get(), 2);
  }
  if (!blas_get)
    GTEST_SKIP() << "the loaded BLAS is not OpenBLAS: only the OpenMP count was checked";
}

}  // namespace
}  // namespace isospring::analysis
