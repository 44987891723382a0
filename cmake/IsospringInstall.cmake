# `cmake --install BUILD --prefix P` layout (docs/architecture.md, "Install layout"):
#   P/lib/libisospring_<module>.a          the static libraries (position-independent code)
#   P/include/isospring/<module>/*.hpp     their public headers
#   P/bin/isospring                        the program
#   P/lib/cmake/isospring/                 the CMake package: find_package(isospring CONFIG)
#   P/lib/python3/dist-packages/isospring.*.so   the Python module (when built, python/)
# The package's targets are isospring::nurbs ... isospring::workflows; the config file finds their
# dependencies again on the consumer's machine (static libraries: private ones are linked too).
include(GNUInstallDirs)
include(CMakePackageConfigHelpers)

set(ISOSPRING_INSTALL_CMAKEDIR "${CMAKE_INSTALL_LIBDIR}/cmake/isospring"
    CACHE STRING "Where the CMake package of isospring is installed, relative to the prefix")

# Called by isospring_module for each module: the library into the export set, and its headers.
function(isospring_install_module name)
  install(TARGETS isospring_${name} EXPORT isospringTargets
          ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR})
  install(DIRECTORY ${CMAKE_CURRENT_SOURCE_DIR}/include/ DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})
endfunction()

# Called once after every module is defined: the exported targets and the package files.
function(isospring_install_package)
  install(EXPORT isospringTargets NAMESPACE isospring::
          DESTINATION ${ISOSPRING_INSTALL_CMAKEDIR})
  configure_package_config_file(
    ${PROJECT_SOURCE_DIR}/cmake/isospringConfig.cmake.in
    ${PROJECT_BINARY_DIR}/isospringConfig.cmake
    INSTALL_DESTINATION ${ISOSPRING_INSTALL_CMAKEDIR})
  # 0.x releases change the API between minor versions: only the same minor version satisfies a
  # request.
  write_basic_package_version_file(${PROJECT_BINARY_DIR}/isospringConfigVersion.cmake
                                   COMPATIBILITY SameMinorVersion)
  install(FILES ${PROJECT_BINARY_DIR}/isospringConfig.cmake
                ${PROJECT_BINARY_DIR}/isospringConfigVersion.cmake
                ${PROJECT_SOURCE_DIR}/cmake/IsospringSystemLibraries.cmake
                ${PROJECT_SOURCE_DIR}/cmake/IsospringPetsc.cmake
          DESTINATION ${ISOSPRING_INSTALL_CMAKEDIR})
endfunction()
