# Every dependency is a Debian package installed by scripts/setup.sh; nothing is downloaded here.
find_package(Eigen3 3.4 REQUIRED NO_MODULE)
find_package(OpenMP REQUIRED)
find_package(Threads REQUIRED)

# OpenCascade 7.6 (geometry module) and SuiteSparse CHOLMOD (analysis module) have no usable CMake
# package: cmake/IsospringSystemLibraries.cmake locates them for the build and for consumers of
# the installed package alike. The underscore names are kept for the tests and benchmarks.
include(IsospringSystemLibraries)
if(ISOSPRING_SYSTEM_LIBRARIES_MISSING)
  message(FATAL_ERROR "Not found: ${ISOSPRING_SYSTEM_LIBRARIES_MISSING}. Install the Debian "
                      "packages in scripts/debian-packages.txt (bash scripts/setup.sh).")
endif()
add_library(isospring_occt ALIAS isospring::occt)
add_library(isospring_cholmod ALIAS isospring::cholmod)

# PETSc with MPI: the optional distributed backend (`analyze --backend petsc`). AUTO uses it when
# found; ON makes it required; OFF builds without it (--backend petsc then says how to get it).
set(ISOSPRING_WITH_PETSC AUTO CACHE STRING "Build the PETSc/MPI backend: AUTO, ON or OFF")
set_property(CACHE ISOSPRING_WITH_PETSC PROPERTY STRINGS AUTO ON OFF)
set(ISOSPRING_HAVE_PETSC OFF)
if(NOT ISOSPRING_WITH_PETSC STREQUAL "OFF")
  include(IsospringPetsc)
  if(ISOSPRING_PETSC_FOUND)
    set(ISOSPRING_HAVE_PETSC ON)
    message(STATUS "PETSc ${ISOSPRING_PETSC_VERSION} with MPI: the --backend petsc solver is built")
  elseif(ISOSPRING_WITH_PETSC STREQUAL "ON")
    message(FATAL_ERROR "ISOSPRING_WITH_PETSC=ON but PETSc (PETSc.pc) or MPI was not found. "
                        "Install libpetsc-real-dev and openmpi-bin (bash scripts/setup.sh) or "
                        "configure with -DISOSPRING_WITH_PETSC=OFF.")
  else()
    message(STATUS "PETSc/MPI not found: building without the --backend petsc solver "
                   "(Debian: libpetsc-real-dev openmpi-bin)")
  endif()
endif()

find_package(CGAL 5.5 REQUIRED)
find_package(Spectra REQUIRED)
find_package(Ceres 2.1 REQUIRED)
find_package(nlohmann_json 3.10 REQUIRED)
find_package(CLI11 2.1 REQUIRED)
find_package(VTK 9.1 REQUIRED COMPONENTS CommonCore CommonDataModel IOXML IOLegacy)

# MuJoCo (Debian: libmujoco-dev): the MJCF export's tests and the runtime's MuJoCo example
# (examples/mujoco); everything else builds without it.
find_package(mujoco QUIET)
if(ISOSPRING_BUILD_TESTS)
  find_package(GTest REQUIRED)
  include(GoogleTest)
endif()
if(ISOSPRING_BUILD_BENCH)
  find_package(benchmark REQUIRED)
endif()
