# CTest driver of Install.ConsumerBuildsAgainstInstalledPackage (tests/install/CMakeLists.txt):
#   1. cmake --install BUILD_DIR --prefix PREFIX (a fresh folder);
#   2. the installed program analyses CASE, calibrates CALIBRATE_CASE and identifies IDENTIFY_CASE
#      (their report.json files are the reference);
#   3. the consumer project (tests/install/consumer) is configured with only
#      -DCMAKE_PREFIX_PATH=PREFIX, built, and run on PATCH, the cases and those reports; its C
#      program runs the engine runtime on the calibrated model.json;
#   4. every installed header compiles on its own with the package's targets;
#   5. with PYTHON (the Python module is built): the installed module imports from
#      PREFIX/lib/python3/dist-packages and keeps the refined annulus' arc at radius 1.
# Variables: BUILD_DIR, PREFIX, WORK, CONSUMER_DIR, PATCH, CASE, CALIBRATE_CASE, IDENTIFY_CASE,
# CXX_COMPILER, BUILD_TYPE, optional PYTHON.
cmake_minimum_required(VERSION 3.22)

function(run)
  execute_process(COMMAND ${ARGN} RESULT_VARIABLE status OUTPUT_VARIABLE out ERROR_VARIABLE out)
  if(NOT status EQUAL 0)
    string(REPLACE ";" " " command "${ARGN}")
    message(FATAL_ERROR "failed (${status}): ${command}\n${out}")
  endif()
  set(last_output "${out}" PARENT_SCOPE)
endfunction()

file(REMOVE_RECURSE ${PREFIX} ${WORK})
file(MAKE_DIRECTORY ${WORK})

run(${CMAKE_COMMAND} --install ${BUILD_DIR} --prefix ${PREFIX})
foreach(installed bin/isospring include/isospring/nurbs/patch.hpp include/isospring/io/case_file.hpp
                  include/isospring/runtime/runtime.h
                  lib/cmake/isospring/isospringConfig.cmake
                  lib/cmake/isospring/isospringConfigVersion.cmake
                  lib/cmake/isospring/isospringTargets.cmake)
  if(NOT EXISTS ${PREFIX}/${installed})
    message(FATAL_ERROR "not installed: PREFIX/${installed}")
  endif()
endforeach()

run(${PREFIX}/bin/isospring analyze ${CASE} -o ${WORK}/analyze -q)
run(${PREFIX}/bin/isospring calibrate ${CALIBRATE_CASE} -o ${WORK}/calibrate -q)
run(${PREFIX}/bin/isospring identify ${IDENTIFY_CASE} -o ${WORK}/identify -q)

set(launcher "")
find_program(ccache_program ccache)
if(ccache_program)
  set(launcher -DCMAKE_CXX_COMPILER_LAUNCHER=${ccache_program})
endif()
run(${CMAKE_COMMAND} -S ${CONSUMER_DIR} -B ${WORK}/consumer-build -DCMAKE_PREFIX_PATH=${PREFIX}
    -DCMAKE_CXX_COMPILER=${CXX_COMPILER} -DCMAKE_BUILD_TYPE=${BUILD_TYPE} ${launcher}
    -DCMAKE_FIND_USE_PACKAGE_REGISTRY=OFF)
# The package must come from the prefix, not from the build tree or a system copy.
file(STRINGS ${WORK}/consumer-build/CMakeCache.txt found REGEX "^isospring_DIR:")
if(NOT found STREQUAL "isospring_DIR:PATH=${PREFIX}/lib/cmake/isospring")
  message(FATAL_ERROR "the consumer found isospring elsewhere: ${found}")
endif()
run(${CMAKE_COMMAND} --build ${WORK}/consumer-build)

# Every installed header compiles with what the package's targets give a consumer: a header
# that needed a private dependency (OpenCascade, CGAL, Ceres, VTK, Spectra) or a file that was
# not installed would fail here.
file(GLOB headers RELATIVE ${PREFIX}/include ${PREFIX}/include/isospring/*/*.hpp
     ${PREFIX}/include/isospring/*/*.h)
set(includes "")
foreach(header ${headers})
  string(APPEND includes "#include <${header}>\n")
endforeach()
file(WRITE ${WORK}/headers/all_headers.cpp "${includes}")
file(WRITE ${WORK}/headers/CMakeLists.txt [=[
cmake_minimum_required(VERSION 3.22)
project(isospring_headers LANGUAGES CXX)
find_package(isospring CONFIG REQUIRED)
add_library(all_headers OBJECT all_headers.cpp)
target_link_libraries(all_headers PRIVATE isospring::workflows)
]=])
run(${CMAKE_COMMAND} -S ${WORK}/headers -B ${WORK}/headers-build -DCMAKE_PREFIX_PATH=${PREFIX}
    -DCMAKE_CXX_COMPILER=${CXX_COMPILER} -DCMAKE_BUILD_TYPE=${BUILD_TYPE} ${launcher}
    -DCMAKE_FIND_USE_PACKAGE_REGISTRY=OFF)
run(${CMAKE_COMMAND} --build ${WORK}/headers-build)
list(LENGTH headers count)
message("every installed header compiles: ${count} headers")

run(${WORK}/consumer-build/consumer ${PATCH} ${CASE} ${WORK}/analyze/report.json
    ${CALIBRATE_CASE} ${WORK}/calibrate/report.json ${IDENTIFY_CASE} ${WORK}/identify/report.json)
message("${last_output}")
# The runtime from C on the model the installed program calibrated.
run(${WORK}/consumer-build/runtime_consumer ${WORK}/calibrate/model.json)
message("${last_output}")

if(PYTHON)
  set(code [=[
import sys, isospring
assert isospring.__file__.startswith(sys.argv[1]), isospring.__file__
patch = isospring.refine_uniform(isospring.elevate_degree(isospring.read_patch_file(sys.argv[2])[0], 1), 4)
x = patch.evaluate([0.5, 0.0])[0]
assert abs((x[0] ** 2 + x[1] ** 2) ** 0.5 - 1) < 1e-12, x
print("python: the installed module at", isospring.__file__, "evaluates", list(x))
]=])
  set(ENV{PYTHONPATH} ${PREFIX}/lib/python3/dist-packages)
  run(${PYTHON} -c "${code}" ${PREFIX}/lib/python3/dist-packages ${PATCH})
  message("${last_output}")
endif()
