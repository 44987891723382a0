#!/usr/bin/env bash
# The sanitizer job of CI (.ci/run, after scripts/test.sh): a clang RelWithDebInfo build with
# AddressSanitizer + UndefinedBehaviorSanitizer (-fno-sanitize-recover=all, halt_on_error=1) in
# ./build-asan of the libraries, the program, the tests CTest labels `sanitize` and the libFuzzer
# harnesses; then runs those tests and a short fuzz run (scripts/fuzz.sh, FUZZ_SECONDS per
# harness, default 30). The `sanitize` tests: the nurbs and io unit tests (the readers) and
# test_apps_sanitize, end-to-end runs of the sanitized program on good and bad inputs (the whole
# bad-input table). Not in it, to stay within CI's time: the geometry, analysis and
# fitting unit tests and the rest of test_apps (under ASan the CAD tests alone take 7 minutes of
# CPU), and the generalised calibration below (5 minutes under ASan). Nor the PETSc backend
# (tests label `mpi`): this build is configured without PETSc, because OpenMPI's and PETSc's
# allocations kept until exit (and OpenMPI's library constructors) flood LeakSanitizer, and the
# ranks mpirun starts would each need the suppressions; the serial code paths are all covered.
#   bash scripts/sanitize.sh [extra ctest arguments]
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
build="${ISOSPRING_ASAN_BUILD_DIR:-$root/build-asan}"
jobs="${ISOSPRING_JOBS:-$(nproc)}"
# ccache hashes the paths inside the tree relative to it (and not the build folder), so that
# another clone of the same commit, such as CI's fresh one, hits the cache of earlier builds.
export CCACHE_BASEDIR="${CCACHE_BASEDIR:-$root}"
export CCACHE_NOHASHDIR="${CCACHE_NOHASHDIR:-1}"
cmake -S "$root" -B "$build" -DCMAKE_CXX_COMPILER=clang++ -DCMAKE_BUILD_TYPE=RelWithDebInfo \
  -DISOSPRING_SANITIZE=ON -DISOSPRING_BUILD_FUZZ=ON -DISOSPRING_BUILD_TESTS=ON \
  -DISOSPRING_BUILD_BENCH=OFF -DISOSPRING_WITH_PETSC=OFF >/dev/null
cmake --build "$build" -j "$jobs" --target isospring test_nurbs test_io test_apps_sanitize \
  fuzz_case_file fuzz_patch_file fuzz_model_file fuzz_markers_csv fuzz_step fuzz_iges
source "$root/scripts/sanitizer-options.sh"
(cd "$build" && ctest --output-on-failure -j "$jobs" -L sanitize \
  -E '^Calibrate[.]GeneralisedSquareReportsEveryHeldOutCaseAndFlagsTheTarget$' "$@")
bash "$root/scripts/fuzz.sh" "${FUZZ_SECONDS:-30}"
