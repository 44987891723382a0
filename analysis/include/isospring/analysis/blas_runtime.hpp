#pragma once
// The BLAS/LAPACK behind CHOLMOD as this process actually loaded it, and thread settings that do
// not spin on a loaded machine.
//
// CHOLMOD calls the Fortran BLAS/LAPACK symbols (dgemm_, dpotrf_, ...) of whatever libblas.so.3
// and liblapack.so.3 the dynamic linker resolved: on Debian the alternatives system chooses
// (ATLAS, OpenBLAS, the reference BLAS), and LD_LIBRARY_PATH can override it. The supernodal
// factorisation spends most of its time there, so which library it is decides the factorisation
// time (reported by `analyze` in report.json and report.md).
#include <string>
#include <string_view>
#include <vector>

namespace isospring::analysis {

struct BlasRuntime {
  /// "OpenBLAS", "ATLAS", "reference BLAS", "BLIS", "MKL", "unknown"; empty when no BLAS is
  /// loaded.
  std::string name;
  /// The library doing the work, symlinks resolved: OpenBLAS's core library
  /// (libopenblasp-r0.3.21.so) when OpenBLAS, else the object defining dgemm_.
  std::string library;
  /// The object defining dpotrf_ (LAPACK), symlinks resolved; empty when none is loaded.
  std::string lapack;
  /// OpenBLAS only: openblas_get_config() (version, kernel, threading) and its thread count.
  std::string config;
  int threads = 0;
  /// Every loaded object whose file name looks like a BLAS/LAPACK (symlinks resolved), in load
  /// order; more than one BLAS here usually means two libraries were linked in by mistake.
  std::vector<std::string> loaded;
};

/// The vendor of a BLAS/LAPACK library from its resolved path ("unknown" when none matches).
std::string blas_vendor(std::string_view path);

/// Whether a file name (path allowed) is a BLAS/LAPACK library of a known kind.
bool is_blas_library(std::string_view path);

/// Inspects the running process (dlsym/dladdr of dgemm_ and dpotrf_, dl_iterate_phdr).
BlasRuntime loaded_blas();

/// Sets OMP_WAIT_POLICY=passive when the user has set neither it nor GOMP_SPINCOUNT: CHOLMOD's
/// OpenMP threads otherwise spin up to 300000 iterations at each barrier (libgomp's default),
/// which on a loaded machine takes the CPU from the threads doing the work. Returns whether it
/// set it. Only processes started afterwards see it: libgomp reads its environment once, in its
/// library constructor, before main runs.
bool set_passive_wait_policy();

/// For a program's main, first thing: when set_passive_wait_policy() changed the environment,
/// re-executes the program (/proc/self/exe, same arguments) so that its own libgomp starts with
/// it; returns (and the program runs on with libgomp's defaults) only when that is not needed or
/// the exec fails. Setting the variable from main would be too late, and setting it from an
/// executable's .preinit_array is lost: glibc installs the process environment after that runs.
void restart_with_passive_threads(char** argv);

}  // namespace isospring::analysis
