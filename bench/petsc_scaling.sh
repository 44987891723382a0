#!/usr/bin/env bash
# Scaling of the PETSc backend: `isospring analyze --backend petsc` on a clamped unit
# cube (degree 2, N^3 elements, (N+2)^3 control points, 3 (N+2)^3 DOFs, one end traction) with 1
# and 2 MPI ranks, and the serial direct solver (CHOLMOD) where it fits. Prints one table row per
# run: DOFs, backend, ranks, assembly / preconditioner setup / solve / wall seconds, CG
# iterations, peak resident memory of the largest rank (GNU time's %M) and the sum over ranks.
# Without result.vtm (--vtk-samples 0): the table times the solver, not the ParaView output.
#   bash bench/petsc_scaling.sh [BUILD_DIR] [N ...]     (default: build, N = 8 16 24 32 40)
# Environment: RANKS ("1 2"), SERIAL_MAX_N (24: largest N also run with the direct solver),
# PETSC_OPTIONS (passed to PETSc, e.g. "-pc_type hypre").
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
build="${1:-$root/build}"
shift || true
sizes=("$@")
((${#sizes[@]})) || sizes=(8 16 24 32 40)
ranks_list="${RANKS:-1 2}"
serial_max="${SERIAL_MAX_N:-24}"
program="$build/apps/isospring"
work="$(mktemp -d /tmp/isospring-petsc-scaling.XXXXXX)"
trap 'rm -rf "$work"' EXIT
root_flag=""
[[ $(id -u) -eq 0 ]] && root_flag="--allow-run-as-root"

printf '%9s %-7s %5s %9s %9s %9s %9s %6s %11s %11s\n' DOFs backend ranks assembly setup solve \
  wall iters "peak MB/rk" "sum MB"
for n in "${sizes[@]}"; do
  case_file="$work/cube_$n.json"
  cat >"$case_file" <<JSON
{
  "schema_version": 1,
  "name": "cube_$n",
  "description": "Unit cube clamped at x = 0, shear traction on x = 1 (bench/petsc_scaling.sh).",
  "units": "SI",
  "geometry": {"type": "box", "size": [1.0, 1.0, 1.0]},
  "discretization": {"degree": [2, 2, 2], "elements": [$n, $n, $n]},
  "material": {"E": 1.0e6, "nu": 0.3},
  "boundary": [{"side": "u0", "fix": ["x", "y", "z"]}],
  "load_cases": [{"id": "shear", "tractions": [{"side": "u1", "value": [0, 0, -1000.0]}]}]
}
JSON
  runs=()
  ((n <= serial_max)) && runs+=("serial 1")
  for r in $ranks_list; do runs+=("petsc $r"); done
  for run in "${runs[@]}"; do
    read -r backend ranks <<<"$run"
    out="$work/out_${n}_${backend}_$ranks"
    : >"$work/rss"
    begin=$(date +%s.%N)
    if [[ $backend == serial ]]; then
      OMP_NUM_THREADS=1 /usr/bin/time -a -o "$work/rss" -f '%M' \
        "$program" analyze "$case_file" -o "$out" -q --threads 1 --vtk-samples 0
    else
      mpirun -np "$ranks" $root_flag --oversubscribe /usr/bin/time -a -o "$work/rss" -f '%M' \
        "$program" analyze "$case_file" -o "$out" -q --backend petsc --vtk-samples 0
    fi
    end=$(date +%s.%N)
    python3 - "$out/report.json" "$work/rss" "$backend" "$ranks" "$begin" "$end" <<'PY'
import json, sys
report = json.load(open(sys.argv[1]))
rss = [int(line) / 1024 for line in open(sys.argv[2]) if line.strip()]
lc = report["load_cases"][0]
print("%9d %-7s %5s %9.2f %9.2f %9.2f %9.2f %6s %11.0f %11.0f" % (
    report["dofs"], sys.argv[3], sys.argv[4], report["assembly_seconds"],
    report["factorization_seconds"], lc["solve_seconds"], float(sys.argv[6]) - float(sys.argv[5]),
    lc.get("iterations", "-"), max(rss), sum(rss)))
PY
  done
done
