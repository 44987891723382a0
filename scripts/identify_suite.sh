#!/usr/bin/env bash
# The unseen-data suite of `isospring identify` (examples/identify_suite/README.md).
#
#   bash scripts/identify_suite.sh generate [DATASET...]
#                                             regenerate every dataset (or the ones named) with
#                                             CalculiX (ccx): examples/identify_suite/<dataset>/
#                                             {case.json, markers.csv, truth.json}; about 100 s of
#                                             CPU per cantilever dataset
#   bash scripts/identify_suite.sh table      run `isospring identify` on every dataset and print
#                                             the per-dataset table and the confusion matrix
#                                             (Markdown); exit 1 when a dataset is misidentified
#
# Both build what they need first (scripts/build.sh with the tests on). The suite's CTest
# tests (label identify_suite) check the same datasets in the normal test run.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
build="${ISOSPRING_BUILD_DIR:-$root/build}"
mode="${1:-}"
case "$mode" in
  generate | table) ;;
  *)
    echo "usage: bash scripts/identify_suite.sh generate|table" >&2
    exit 2
    ;;
esac
bash "$root/scripts/build.sh" -DISOSPRING_BUILD_TESTS=ON >/dev/null
generator="$build/tests/identify_suite/generate_identify_suite"
if [[ "$mode" == generate ]]; then
  exec "$generator" generate "$root/examples/identify_suite" "${@:2}"
fi
exec "$generator" table "$root/examples/identify_suite" "$build/apps/isospring" \
  "$build/identify_suite_runs"
