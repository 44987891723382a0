// The BLAS/LAPACK detection against the process's own memory map (/proc/self/maps, an
// independent record of what the dynamic linker mapped), and the thread environment policy.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <optional>
#include <string>

#include "isospring/analysis/blas_runtime.hpp"

using namespace isospring::analysis;

namespace {

bool mapped(const std::string& path) {
  std::ifstream maps("/proc/self/maps");
  std::string line;
  while (std::getline(maps, line))
    if (line.size() >= path.size() &&
        line.compare(line.size() - path.size(), path.size(), path) == 0)
      return true;
  return false;
}

// Restores an environment variable on scope exit.
class SavedVariable {
 public:
  explicit SavedVariable(const char* name) : name_(name) {
    if (const char* value = std::getenv(name)) value_ = value;
  }
  ~SavedVariable() {
    if (value_)
      setenv(name_, value_->c_str(), 1);
    else
      unsetenv(name_);
  }
  SavedVariable(const SavedVariable&) = delete;
  SavedVariable& operator=(const SavedVariable&) = delete;

 private:
  const char* name_;
  std::optional<std::string> value_;
};

}  // namespace

TEST(BlasRuntime, VendorsOfDebianLibraryPaths) {
  EXPECT_EQ(blas_vendor("/usr/lib/x86_64-linux-gnu/openblas-pthread/libopenblasp-r0.3.21.so"),
            "OpenBLAS");
  EXPECT_EQ(blas_vendor("/usr/lib/x86_64-linux-gnu/openblas-openmp/libblas.so.3"), "OpenBLAS");
  EXPECT_EQ(blas_vendor("/usr/lib/x86_64-linux-gnu/atlas/libblas.so.3.10.3"), "ATLAS");
  EXPECT_EQ(blas_vendor("/usr/lib/x86_64-linux-gnu/libf77blas.so.3.10.3"), "ATLAS");
  EXPECT_EQ(blas_vendor("/usr/lib/x86_64-linux-gnu/blas/libblas.so.3.11.0"), "reference BLAS");
  EXPECT_EQ(blas_vendor("/usr/lib/x86_64-linux-gnu/lapack/liblapack.so.3.11.0"), "reference BLAS");
  EXPECT_EQ(blas_vendor("/usr/lib/x86_64-linux-gnu/blis-openmp/libblas.so.3"), "BLIS");
  EXPECT_EQ(blas_vendor("/opt/intel/oneapi/mkl/lib/libmkl_rt.so.2"), "MKL");
  EXPECT_EQ(blas_vendor("/usr/lib/x86_64-linux-gnu/libcholmod.so.3"), "unknown");
}

TEST(BlasRuntime, RecognisesBlasFileNamesOnly) {
  EXPECT_TRUE(is_blas_library("/usr/lib/x86_64-linux-gnu/libblas.so.3"));
  EXPECT_TRUE(is_blas_library("liblapack.so.3"));
  EXPECT_TRUE(is_blas_library("/x/openblas-pthread/libopenblasp-r0.3.21.so"));
  EXPECT_FALSE(is_blas_library("/usr/lib/x86_64-linux-gnu/libcholmod.so.3"));
  EXPECT_FALSE(is_blas_library("/usr/lib/x86_64-linux-gnu/atlas/libsuitesparseconfig.so"));
}

TEST(BlasRuntime, ReportsTheMappedLibraryThatCholmodCalls) {
  // This program links CHOLMOD, which needs libblas.so.3 and liblapack.so.3.
  const BlasRuntime blas = loaded_blas();
  ASSERT_FALSE(blas.name.empty());
  EXPECT_NE(blas.name, "unknown") << blas.library;
  EXPECT_EQ(blas_vendor(blas.library), blas.name);
  EXPECT_TRUE(std::filesystem::path(blas.library).is_absolute()) << blas.library;
  EXPECT_TRUE(mapped(blas.library)) << blas.library << " is not in /proc/self/maps";
  ASSERT_FALSE(blas.lapack.empty());
  EXPECT_TRUE(mapped(blas.lapack)) << blas.lapack;
  ASSERT_FALSE(blas.loaded.empty());
  for (const std::string& path : blas.loaded) EXPECT_TRUE(mapped(path)) << path;
  EXPECT_NE(std::find(blas.loaded.begin(), blas.loaded.end(), blas.library), blas.loaded.end());
  if (blas.name == "OpenBLAS") {
    EXPECT_EQ(blas.config.rfind("OpenBLAS", 0), 0u) << blas.config;
    EXPECT_GE(blas.threads, 1);
  } else {
    EXPECT_EQ(blas.config, "");
  }
}

TEST(BlasRuntime, PassiveWaitPolicyOnlyWhenTheUserChoseNone) {
  const SavedVariable policy("OMP_WAIT_POLICY"), spin("GOMP_SPINCOUNT");
  unsetenv("OMP_WAIT_POLICY");
  unsetenv("GOMP_SPINCOUNT");
  EXPECT_TRUE(set_passive_wait_policy());
  ASSERT_NE(std::getenv("OMP_WAIT_POLICY"), nullptr);
  EXPECT_STREQ(std::getenv("OMP_WAIT_POLICY"), "passive");
  EXPECT_FALSE(set_passive_wait_policy());  // already set

  setenv("OMP_WAIT_POLICY", "active", 1);
  EXPECT_FALSE(set_passive_wait_policy());
  EXPECT_STREQ(std::getenv("OMP_WAIT_POLICY"), "active");

  unsetenv("OMP_WAIT_POLICY");
  setenv("GOMP_SPINCOUNT", "1000", 1);  // a spin count is a choice too
  EXPECT_FALSE(set_passive_wait_policy());
  EXPECT_EQ(std::getenv("OMP_WAIT_POLICY"), nullptr);
}
