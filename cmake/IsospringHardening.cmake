# Sanitizer and fuzzing instrumentation for every target of the project (docs/hardening.md).
#
# ISOSPRING_SANITIZE: AddressSanitizer + UndefinedBehaviorSanitizer; any UB report is fatal
# (-fno-sanitize-recover=all), as are ASan's (ASan always halts on its first error). Meant for a
# RelWithDebInfo build in its own folder (scripts/sanitize.sh: ./build-asan).
# ISOSPRING_BUILD_FUZZ: the libraries get libFuzzer's coverage instrumentation
# (-fsanitize=fuzzer-no-link) and fuzz/ builds one libFuzzer program per reader; needs clang.
if(ISOSPRING_SANITIZE)
  # -gline-tables-only: the sanitizers' stack traces need file:line only; full debug information
  # of the OpenCascade/VTK/CGAL/Ceres headers would double compile and link times.
  add_compile_options(-fsanitize=address,undefined -fno-sanitize-recover=all
                      -fno-omit-frame-pointer)
  if(CMAKE_CXX_COMPILER_ID MATCHES "Clang")
    add_compile_options(-gline-tables-only)
  endif()
  add_link_options(-fsanitize=address,undefined)
endif()

if(ISOSPRING_BUILD_FUZZ)
  if(NOT CMAKE_CXX_COMPILER_ID MATCHES "Clang")
    message(FATAL_ERROR "ISOSPRING_BUILD_FUZZ needs clang (libFuzzer): configure with "
                        "-DCMAKE_CXX_COMPILER=clang++ (Debian packages clang, libclang-rt-14-dev)")
  endif()
  if(NOT ISOSPRING_SANITIZE)
    # The coverage hooks of -fsanitize=fuzzer-no-link are defined by the sanitizer runtime, which
    # the tests and the program then need too; and a fuzzer without ASan finds only crashes.
    message(FATAL_ERROR "ISOSPRING_BUILD_FUZZ needs ISOSPRING_SANITIZE=ON")
  endif()
  add_compile_options(-fsanitize=fuzzer-no-link)
endif()
