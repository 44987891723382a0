# OpenCascade and CHOLMOD as the imported targets isospring::occt and isospring::cholmod.
#
# Neither ships a CMake package isospring can use (Debian's OpenCASCADEConfig.cmake insists on
# the visualization and OCAF packages, which isospring does not need; SuiteSparse 5 has none), so
# they are located directly. The same file serves the build (cmake/IsospringDependencies.cmake)
# and the installed package (isospringConfig.cmake): the libraries are static, so a consumer
# links OpenCascade and CHOLMOD too, and finds them the same way on its own machine instead of
# inheriting the absolute paths of the machine isospring was built on.
#
# Sets ISOSPRING_SYSTEM_LIBRARIES_MISSING to the names of what was not found (empty: all found);
# the caller decides whether that is fatal.
set(ISOSPRING_SYSTEM_LIBRARIES_MISSING "")

if(NOT TARGET isospring::occt)
  find_path(OCCT_INCLUDE_DIR Standard_Version.hxx PATH_SUFFIXES opencascade)
  set(_isospring_occt_libraries "")
  foreach(_isospring_toolkit TKernel TKMath TKG2d TKG3d TKGeomBase TKBRep TKGeomAlgo TKTopAlgo
                             TKPrim TKBO TKShHealing TKBool TKMesh TKOffset TKFillet TKXSBase
                             TKSTEPBase TKSTEPAttr TKSTEP209 TKSTEP TKIGES)
    find_library(OCCT_${_isospring_toolkit} ${_isospring_toolkit})
    if(OCCT_${_isospring_toolkit})
      list(APPEND _isospring_occt_libraries ${OCCT_${_isospring_toolkit}})
    else()
      list(APPEND ISOSPRING_SYSTEM_LIBRARIES_MISSING "OpenCascade ${_isospring_toolkit}")
    endif()
  endforeach()
  if(NOT OCCT_INCLUDE_DIR)
    list(APPEND ISOSPRING_SYSTEM_LIBRARIES_MISSING "OpenCascade headers (Standard_Version.hxx)")
  endif()
  add_library(isospring::occt INTERFACE IMPORTED)
  if(OCCT_INCLUDE_DIR)
    target_include_directories(isospring::occt SYSTEM INTERFACE ${OCCT_INCLUDE_DIR})
  endif()
  target_link_libraries(isospring::occt INTERFACE ${_isospring_occt_libraries})
endif()

if(NOT TARGET isospring::cholmod)
  # SuiteSparse CHOLMOD, used through Eigen's CholmodSupport (analysis module).
  find_path(CHOLMOD_INCLUDE_DIR cholmod.h PATH_SUFFIXES suitesparse)
  find_library(CHOLMOD_LIBRARY cholmod)
  foreach(_isospring_var CHOLMOD_INCLUDE_DIR CHOLMOD_LIBRARY)
    if(NOT ${_isospring_var})
      list(APPEND ISOSPRING_SYSTEM_LIBRARIES_MISSING "${_isospring_var}")
    endif()
  endforeach()
  add_library(isospring::cholmod INTERFACE IMPORTED)
  if(CHOLMOD_INCLUDE_DIR AND CHOLMOD_LIBRARY)
    target_include_directories(isospring::cholmod SYSTEM INTERFACE ${CHOLMOD_INCLUDE_DIR})
    target_link_libraries(isospring::cholmod INTERFACE ${CHOLMOD_LIBRARY})
  endif()
  # CHOLMOD's BLAS/LAPACK calls bind to the first library in the program's load order that
  # defines them. Debian's libceres-dev hard-wires ATLAS into its link interface (libf77blas,
  # libatlas), so ATLAS's libf77blas.so.3 was a direct dependency of every program and CHOLMOD's
  # dgemm_ went to ATLAS whatever libblas.so.3 is (the alternatives system, LD_LIBRARY_PATH). The
  # generic libblas.so.3 and liblapack.so.3 come first instead (kept by --no-as-needed: the
  # programs call no BLAS themselves); `analyze` reports the library that is bound
  # (analysis/blas_runtime.hpp). Consumers of the installed package get the same order.
  target_link_options(isospring::cholmod INTERFACE
                      "LINKER:--push-state,--no-as-needed,-lblas,-llapack,--pop-state")
endif()
