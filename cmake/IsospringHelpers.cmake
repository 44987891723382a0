# isospring_module(NAME DEPS...): the library isospring_NAME (alias isospring::NAME) built from
# NAME/src/**/*.cpp (subfolders group a module's sources by subject) with the public headers in
# NAME/include/isospring/NAME/. Every module is installed (cmake/IsospringInstall.cmake) as
# isospring::NAME of the exported package.
function(isospring_module name)
  cmake_parse_arguments(ARG "" "" "PUBLIC;PRIVATE" ${ARGN})
  file(GLOB_RECURSE sources CONFIGURE_DEPENDS ${CMAKE_CURRENT_SOURCE_DIR}/src/*.cpp)
  # Headers from the source tree while building, from PREFIX/include once installed.
  set(include_dirs $<BUILD_INTERFACE:${CMAKE_CURRENT_SOURCE_DIR}/include>
                   $<INSTALL_INTERFACE:${CMAKE_INSTALL_INCLUDEDIR}>)
  if(NOT sources)
    # A module still being written: header-only until its first source lands.
    add_library(isospring_${name} INTERFACE)
    target_include_directories(isospring_${name} INTERFACE ${include_dirs})
    target_link_libraries(isospring_${name} INTERFACE ${ARG_PUBLIC})
    target_compile_features(isospring_${name} INTERFACE cxx_std_20)
  else()
    add_library(isospring_${name} STATIC ${sources})
    # A module's private headers are found from its src/ root, whichever subfolder includes them.
    target_include_directories(isospring_${name} PUBLIC ${include_dirs}
                               PRIVATE ${CMAKE_CURRENT_SOURCE_DIR}/src)
    target_link_libraries(isospring_${name} PUBLIC ${ARG_PUBLIC} PRIVATE ${ARG_PRIVATE})
    # The public headers are C++20: consumers of the installed package get the standard too.
    target_compile_features(isospring_${name} PUBLIC cxx_std_20)
    # Position-independent code, so that the static libraries can go into shared objects: the
    # Python module (python/) and a user's own shared library or plugin.
    set_target_properties(isospring_${name} PROPERTIES POSITION_INDEPENDENT_CODE ON)
    isospring_warnings(isospring_${name})
  endif()
  add_library(isospring::${name} ALIAS isospring_${name})
  set_target_properties(isospring_${name} PROPERTIES EXPORT_NAME ${name})
  isospring_install_module(${name})
endfunction()

function(isospring_warnings target)
  # -Wno-restrict: GCC 12 reports std::string concatenation as overlapping memcpy at -O2
  # (GCC bug 105329, a false positive in libstdc++ headers).
  target_compile_options(${target} PRIVATE -Wall -Wextra
    $<$<AND:$<CXX_COMPILER_ID:GNU>,$<VERSION_LESS:$<CXX_COMPILER_VERSION>,13>>:-Wno-restrict>)
endfunction()

# isospring_test_suite(NAME LIBS... [SOURCES files...] [LABELS labels...]): one GoogleTest program
# test_NAME, from tests/NAME/*.cpp unless SOURCES are given, registered with CTest (label NAME
# plus LABELS, e.g. `sanitize` for the subset of the sanitizer job, scripts/sanitize.sh). Tests
# find the repository and ../shared through compile definitions so they run from any build
# directory.
function(isospring_test_suite name)
  cmake_parse_arguments(ARG "" "" "SOURCES;LABELS" ${ARGN})
  if(ARG_SOURCES)
    set(sources ${ARG_SOURCES})
  else()
    file(GLOB sources CONFIGURE_DEPENDS ${CMAKE_CURRENT_SOURCE_DIR}/*.cpp)
  endif()
  if(NOT sources)
    return()
  endif()
  add_executable(test_${name} ${sources})
  target_link_libraries(test_${name} PRIVATE ${ARG_UNPARSED_ARGUMENTS} GTest::gtest
                                              GTest::gtest_main)
  target_compile_definitions(test_${name} PRIVATE
    ISOSPRING_SOURCE_DIR="${PROJECT_SOURCE_DIR}"
    ISOSPRING_SHARED_DIR="${PROJECT_SOURCE_DIR}/../shared"
    ISOSPRING_BINARY_DIR="${PROJECT_BINARY_DIR}"
    ISOSPRING_EXECUTABLE="$<TARGET_FILE:isospring>")
  target_include_directories(test_${name} PRIVATE ${PROJECT_SOURCE_DIR}/tests/common)
  isospring_warnings(test_${name})
  gtest_discover_tests(test_${name} PROPERTIES LABELS ${name} DISCOVERY_TIMEOUT 60)
  if(ARG_LABELS)
    # gtest_discover_tests flattens a list of labels into separate property arguments; the extra
    # labels are set after its discovered tests are included, through the list it defines.
    set(labels_file "${CMAKE_CURRENT_BINARY_DIR}/test_${name}_labels.cmake")
    file(WRITE "${labels_file}"
         "if(test_${name}_TESTS)\n"
         "  set_tests_properties(\${test_${name}_TESTS} PROPERTIES LABELS \"${name};${ARG_LABELS}\")\n"
         "endif()\n")
    set_property(DIRECTORY APPEND PROPERTY TEST_INCLUDE_FILES "${labels_file}")
  endif()
endfunction()
