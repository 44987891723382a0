#!/usr/bin/env bash
# Configures and builds isospring (Release) in ./build; used by demo.sh and test.sh.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
build="${ISOSPRING_BUILD_DIR:-$root/build}"
jobs="${ISOSPRING_JOBS:-$(nproc)}"
cmake -S "$root" -B "$build" -DCMAKE_BUILD_TYPE=Release "$@" >/dev/null
cmake --build "$build" -j "$jobs"
