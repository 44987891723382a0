#!/usr/bin/env bash
# Configures and builds isospring (Release) in ./build; used by demo.sh and test.sh.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
build="${ISOSPRING_BUILD_DIR:-$root/build}"
jobs="${ISOSPRING_JOBS:-$(nproc)}"
# ccache hashes the paths inside the tree relative to it (and not the build folder), so that
# another clone of the same commit, such as CI's fresh one, hits the cache of earlier builds.
export CCACHE_BASEDIR="${CCACHE_BASEDIR:-$root}"
export CCACHE_NOHASHDIR="${CCACHE_NOHASHDIR:-1}"
cmake -S "$root" -B "$build" -DCMAKE_BUILD_TYPE=Release "$@" >/dev/null
cmake --build "$build" -j "$jobs"
