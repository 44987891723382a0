#!/usr/bin/env bash
# One command for a fresh Debian machine: install what is missing, build everything (library,
# program, tests, benchmarks) and run the whole test suite with CTest.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
build="${ISOSPRING_BUILD_DIR:-$root/build}"
bash "$root/scripts/setup.sh"
bash "$root/scripts/build.sh" -DISOSPRING_BUILD_TESTS=ON -DISOSPRING_BUILD_BENCH=ON
cd "$build"
ctest --output-on-failure -j "${ISOSPRING_JOBS:-$(nproc)}" "$@"
