# Every dependency is a Debian package installed by scripts/setup.sh; nothing is downloaded here.
find_package(Eigen3 3.4 REQUIRED NO_MODULE)
find_package(OpenMP REQUIRED)
find_package(Threads REQUIRED)

# OpenCascade 7.6: only the toolkits isospring uses (geometry module). Debian's
# OpenCASCADEConfig.cmake insists on the visualization and OCAF packages too, which isospring does
# not need, so the toolkits are located directly.
find_path(OCCT_INCLUDE_DIR Standard_Version.hxx PATH_SUFFIXES opencascade REQUIRED)
add_library(isospring_occt INTERFACE)
target_include_directories(isospring_occt SYSTEM INTERFACE ${OCCT_INCLUDE_DIR})
foreach(toolkit TKernel TKMath TKG2d TKG3d TKGeomBase TKBRep TKGeomAlgo TKTopAlgo TKPrim TKBO
                TKShHealing TKBool TKMesh TKOffset TKFillet TKXSBase TKSTEPBase TKSTEPAttr
                TKSTEP209 TKSTEP TKIGES)
  find_library(OCCT_${toolkit} ${toolkit} REQUIRED)
  target_link_libraries(isospring_occt INTERFACE ${OCCT_${toolkit}})
endforeach()

find_package(CGAL 5.5 REQUIRED)

# SuiteSparse CHOLMOD, used through Eigen's CholmodSupport (analysis module).
find_path(CHOLMOD_INCLUDE_DIR cholmod.h PATH_SUFFIXES suitesparse REQUIRED)
find_library(CHOLMOD_LIBRARY cholmod REQUIRED)
add_library(isospring_cholmod INTERFACE)
target_include_directories(isospring_cholmod SYSTEM INTERFACE ${CHOLMOD_INCLUDE_DIR})
target_link_libraries(isospring_cholmod INTERFACE ${CHOLMOD_LIBRARY})
# CHOLMOD's BLAS/LAPACK calls bind to the first library in the program's load order that defines
# them. Debian's libceres-dev hard-wires ATLAS into its link interface (libf77blas, libatlas), so
# ATLAS's libf77blas.so.3 was a direct dependency of every program and CHOLMOD's dgemm_ went to
# ATLAS whatever libblas.so.3 is (the alternatives system, LD_LIBRARY_PATH). The generic
# libblas.so.3 and liblapack.so.3 come first instead (kept by --no-as-needed: the programs call
# no BLAS themselves); `analyze` reports the library that is bound (analysis/blas_runtime.hpp).
target_link_options(isospring_cholmod INTERFACE
                    "LINKER:--push-state,--no-as-needed,-lblas,-llapack,--pop-state")

find_package(Spectra REQUIRED)
find_package(Ceres 2.1 REQUIRED)
find_package(nlohmann_json 3.10 REQUIRED)
find_package(CLI11 2.1 REQUIRED)
find_package(VTK 9.1 REQUIRED COMPONENTS CommonCore CommonDataModel IOXML IOLegacy)

if(ISOSPRING_BUILD_TESTS)
  find_package(GTest REQUIRED)
  include(GoogleTest)
  find_package(mujoco QUIET)  # only for the MJCF export test
endif()
if(ISOSPRING_BUILD_BENCH)
  find_package(benchmark REQUIRED)
endif()
