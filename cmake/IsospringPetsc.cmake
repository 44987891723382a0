# PETSc (Debian libpetsc-real-dev) and the MPI it is built with, as the imported target
# isospring::petsc: the distributed backend of the IGA reference (analysis/petsc_solver.hpp,
# `isospring analyze --backend petsc`). Like cmake/IsospringSystemLibraries.cmake it serves the
# build and the installed package: the analysis library is static, so a consumer of a PETSc build
# links PETSc and MPI too and finds them here on its own machine.
#
# PETSc ships no CMake package; Debian installs PETSc.pc, which names PETSc's include folder but
# not the one of mpi.h (OpenMPI's), so MPI comes from CMake's FindMPI.
#
# Sets ISOSPRING_PETSC_FOUND (TRUE/FALSE) and, when found, ISOSPRING_PETSC_VERSION.
set(ISOSPRING_PETSC_FOUND FALSE)
if(TARGET isospring::petsc)
  set(ISOSPRING_PETSC_FOUND TRUE)
  return()
endif()
find_package(PkgConfig QUIET)
if(PkgConfig_FOUND)
  pkg_check_modules(ISOSPRING_PETSC_PC QUIET IMPORTED_TARGET PETSc>=3.18)
endif()
# The CXX component (isospring enables no C compiler) with the C API only: PETSc needs no MPI C++
# bindings (deprecated since MPI 2.2).
set(MPI_CXX_SKIP_MPICXX ON CACHE BOOL "MPI C API only (isospring's PETSc backend)")
find_package(MPI QUIET COMPONENTS CXX)
if(ISOSPRING_PETSC_PC_FOUND AND MPI_CXX_FOUND)
  add_library(isospring::petsc INTERFACE IMPORTED)
  target_link_libraries(isospring::petsc INTERFACE PkgConfig::ISOSPRING_PETSC_PC MPI::MPI_CXX)
  set(ISOSPRING_PETSC_FOUND TRUE)
  set(ISOSPRING_PETSC_VERSION ${ISOSPRING_PETSC_PC_VERSION})
endif()
