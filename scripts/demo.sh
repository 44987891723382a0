#!/usr/bin/env bash
# One command for a fresh Debian machine: install what is missing, build, run the main job
# (`isospring demo`) on the shipped default part. Results go to ./isospring-out/.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
bash "$root/scripts/setup.sh"
bash "$root/scripts/build.sh" -DISOSPRING_BUILD_TESTS=OFF -DISOSPRING_BUILD_BENCH=OFF
"${ISOSPRING_BUILD_DIR:-$root/build}/apps/isospring" demo -o isospring-out "$@"
