#include "isospring/analysis/blas_runtime.hpp"

#include <dlfcn.h>
#include <link.h>
#include <unistd.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <system_error>

namespace isospring::analysis {
namespace {

std::string resolved(const char* path) {
  if (!path || !*path) return {};
  std::error_code error;
  const std::filesystem::path canonical = std::filesystem::canonical(path, error);
  return error ? std::string(path) : canonical.string();
}

// The resolved file of the loaded object defining `symbol` in the global scope (where CHOLMOD's
// calls are bound), empty when no loaded object defines it.
std::string defining_object(const char* symbol) {
  void* address = dlsym(RTLD_DEFAULT, symbol);
  Dl_info info{};
  if (!address || !dladdr(address, &info)) return {};
  return resolved(info.dli_fname);
}

bool contains(std::string_view text, std::string_view part) {
  return text.find(part) != std::string_view::npos;
}

}  // namespace

std::string blas_vendor(std::string_view path) {
  std::string lower(path);
  std::transform(lower.begin(), lower.end(), lower.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  if (contains(lower, "openblas")) return "OpenBLAS";
  // ATLAS also installs libf77blas, libcblas and libatlas outside its alternatives folder.
  if (contains(lower, "atlas") || contains(lower, "libf77blas") || contains(lower, "libcblas"))
    return "ATLAS";
  if (contains(lower, "mkl")) return "MKL";
  if (contains(lower, "blis")) return "BLIS";
  // Debian's reference BLAS/LAPACK live in .../blas/ and .../lapack/ (alternatives priority 10).
  if (contains(lower, "/blas/libblas") || contains(lower, "/lapack/liblapack"))
    return "reference BLAS";
  return "unknown";
}

bool is_blas_library(std::string_view path) {
  const std::string_view file = path.substr(path.find_last_of('/') + 1);
  for (std::string_view prefix : {"libblas", "liblapack", "libopenblas", "libatlas", "libf77blas",
                                  "libcblas", "libblis", "libmkl_rt", "libmkl_core"})
    if (file.substr(0, prefix.size()) == prefix) return true;
  return false;
}

BlasRuntime loaded_blas() {
  BlasRuntime runtime;
  dl_iterate_phdr(
      [](dl_phdr_info* info, size_t, void* data) {
        auto& loaded = *static_cast<std::vector<std::string>*>(data);
        const std::string path = resolved(info->dlpi_name);
        if (!path.empty() && (is_blas_library(info->dlpi_name) || is_blas_library(path)) &&
            std::find(loaded.begin(), loaded.end(), path) == loaded.end())
          loaded.push_back(path);
        return 0;
      },
      &runtime.loaded);
  runtime.lapack = defining_object("dpotrf_");
  const std::string dgemm = defining_object("dgemm_");
  if (dgemm.empty()) return runtime;
  runtime.library = dgemm;
  runtime.name = blas_vendor(dgemm);
  // Debian's OpenBLAS libblas.so.3 is a thin interface over libopenblas.so.0; the core library
  // names the version, and its own functions report the build and thread count.
  if (runtime.name != "OpenBLAS") return runtime;
  using ConfigFunction = char* (*)();
  using ThreadsFunction = int (*)();
  if (auto config = reinterpret_cast<ConfigFunction>(dlsym(RTLD_DEFAULT, "openblas_get_config"))) {
    runtime.config = config();
    Dl_info info{};
    if (dladdr(reinterpret_cast<void*>(config), &info) && info.dli_fname)
      runtime.library = resolved(info.dli_fname);
  }
  if (auto threads =
          reinterpret_cast<ThreadsFunction>(dlsym(RTLD_DEFAULT, "openblas_get_num_threads")))
    runtime.threads = threads();
  return runtime;
}

bool set_passive_wait_policy() {
  if (std::getenv("OMP_WAIT_POLICY") || std::getenv("GOMP_SPINCOUNT")) return false;
  return setenv("OMP_WAIT_POLICY", "passive", 0) == 0;
}

void restart_with_passive_threads(char** argv) {
  if (!set_passive_wait_policy()) return;
  execv("/proc/self/exe", argv);  // returns only on failure
}

}  // namespace isospring::analysis
