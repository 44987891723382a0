#!/bin/sh
# Regenerates docs/images/demo_cantilever_von_mises.png (the README picture) from the VTK output
# of `isospring demo`: VTK 9.1 offscreen rendering (Debian python3-vtk9) under a virtual X
# server (Debian xvfb: `apt-get install xvfb python3-vtk9`).
#   scripts/render_readme_image.sh [BUILD_DIR]   (default: build)
set -eu
root=$(cd "$(dirname "$0")/.." && pwd)
build=${1:-"$root/build"}
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
"$build/apps/isospring" demo -o "$work/demo" --quiet
mkdir -p "$root/docs/images"
xvfb-run -a -s "-screen 0 1024x768x24" /usr/bin/python3 "$root/scripts/render_readme_image.py" \
  "$work/demo" "$root/docs/images/demo_cantilever_von_mises.png"
echo "wrote $root/docs/images/demo_cantilever_von_mises.png"
