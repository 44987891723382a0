#!/usr/bin/env bash
# One command for a fresh Debian machine: install what is missing, build everything (library,
# program, tests, benchmarks) and run the whole test suite with CTest.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
build="${ISOSPRING_BUILD_DIR:-$root/build}"
bash "$root/scripts/setup.sh"
bash "$root/scripts/build.sh" -DISOSPRING_BUILD_TESTS=ON -DISOSPRING_BUILD_BENCH=ON
cd "$build"
# The identify unseen-data suite (label identify_suite, 14 CalculiX datasets, up to 25 min of CPU
# each on the 3D ones) runs on its own: ctest -L identify_suite, or scripts/identify_suite.sh table.
ctest --output-on-failure -j "${ISOSPRING_JOBS:-$(nproc)}" -LE identify_suite "$@"
