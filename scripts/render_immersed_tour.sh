#!/bin/sh
# Regenerates docs/images/immersed_rounded_bracket.png (the immersed tour's picture,
# docs/immersed-tour.md) from `isospring analyze examples/immersed/rounded_bracket.json`: VTK 9.1
# offscreen rendering (Debian python3-vtk9) under a virtual X server (Debian xvfb:
# `apt-get install xvfb python3-vtk9`).
#   scripts/render_immersed_tour.sh [BUILD_DIR]   (default: build)
set -eu
root=$(cd "$(dirname "$0")/.." && pwd)
build=${1:-"$root/build"}
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
"$build/apps/isospring" analyze "$root/examples/immersed/rounded_bracket.json" -o "$work/bracket" \
  --quiet
mkdir -p "$root/docs/images"
xvfb-run -a -s "-screen 0 1024x768x24" /usr/bin/python3 "$root/scripts/render_immersed_tour.py" \
  "$work/bracket" "$root/docs/images/immersed_rounded_bracket.png"
echo "wrote $root/docs/images/immersed_rounded_bracket.png"
