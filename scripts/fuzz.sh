#!/usr/bin/env bash
# Runs every libFuzzer harness of fuzz/ (built by scripts/sanitize.sh in ./build-asan) on its seed
# corpus fuzz/corpus/<name>/ for SECONDS each (default 30), two at a time. The repository's corpus
# is only read: new inputs go to a temporary folder. A crash, leak, timeout or out-of-memory
# input fails the run; the input is left in $ISOSPRING_FUZZ_ARTIFACTS (default
# build-asan/fuzz-artifacts) and its log printed.
#   bash scripts/fuzz.sh [SECONDS] [fuzz_name ...]
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
build="${ISOSPRING_ASAN_BUILD_DIR:-$root/build-asan}"
seconds="${1:-30}"
shift || true
targets=("$@")
((${#targets[@]})) || targets=(fuzz_case_file fuzz_patch_file fuzz_model_file fuzz_markers_csv
                               fuzz_step fuzz_iges)
artifacts="${ISOSPRING_FUZZ_ARTIFACTS:-$build/fuzz-artifacts}"
mkdir -p "$artifacts"
work="$(mktemp -d)"
# The harnesses write every input to a file: into memory where there is a /dev/shm.
scratch=/dev/shm
[[ -d $scratch && -w $scratch ]] || scratch="${TMPDIR:-/tmp}"
trap 'rm -rf "$work"' EXIT
source "$root/scripts/sanitizer-options.sh"

# STEP/IGES: the shipped parts are up to 23 KB and one import takes 0.5-4 s in this build (the
# OpenCascade read runs twice, first in a forked child); the revolution parts (torus.step,
# tube.step) take 8-70 s, so they are not seeds.
max_len() {
  case "$1" in
    fuzz_step | fuzz_iges) echo 32768 ;;
    *) echo 4096 ;;
  esac
}
# STEP/IGES: no leak checks. OpenCascade's readers keep memory on many error paths of malformed
# files (scripts/lsan.supp lists the ones fuzzing found); each new malformed input can reach
# another, which would make this run fail at random on third-party memory. isospring's own code
# is leak-checked by the other harnesses and the sanitized tests (CAD import included).
leaks_of() {
  case "$1" in
    fuzz_step | fuzz_iges) echo 0 ;;
    *) echo 1 ;;
  esac
}
timeout_of() {
  case "$1" in
    fuzz_step | fuzz_iges) echo 30 ;;
    *) echo 10 ;;
  esac
}

run_one() {
  local name="$1"
  mkdir -p "$work/$name"
  # -rss_limit_mb: the readers refuse what cannot fit long before 2 GB.
  TMPDIR="$scratch" "$build/fuzz/$name" "$work/$name" "$root/fuzz/corpus/$name" \
    -max_total_time="$seconds" -max_len="$(max_len "$name")" -timeout="$(timeout_of "$name")" \
    -detect_leaks="$(leaks_of "$name")" -rss_limit_mb=2048 -print_final_stats=1 \
    -artifact_prefix="$artifacts/$name-" >"$work/$name.log" 2>&1
}

failed=()
pids=()
names=()
flush() {
  local i
  for i in "${!pids[@]}"; do
    if wait "${pids[$i]}"; then
      grep -E '^stat::(number_of_executed_units|average_exec_per_sec)' "$work/${names[$i]}.log" |
        tr '\n' ' ' | sed "s/^/fuzz: ${names[$i]}: /; s/\$/\n/"
    else
      failed+=("${names[$i]}")
      echo "fuzz: ${names[$i]} FAILED:" >&2
      tail -n 60 "$work/${names[$i]}.log" >&2
    fi
  done
  pids=()
  names=()
}
for name in "${targets[@]}"; do
  run_one "$name" &
  pids+=($!)
  names+=("$name")
  ((${#pids[@]} < ${ISOSPRING_JOBS:-2})) || flush
done
flush
if ((${#failed[@]})); then
  echo "fuzz: ${#failed[@]} harness(es) found a problem: ${failed[*]} (inputs in $artifacts)" >&2
  exit 1
fi
echo "fuzz: ${#targets[@]} harnesses, ${seconds} s each: no crash"
