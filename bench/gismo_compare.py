#!/usr/bin/env python3
"""isospring beside G+Smo on the same cube problems, in one run.

The problem: the unit cube of steel (E 210 GPa, nu 0.3, density 7800 kg/m^3) clamped at x = 0
under its own weight (body force 7800 x 9.81 N/m^3 along -z), degree 2, n^3 elements for each
n of --sizes (8, 16 and 32: 3,000 to 117,912 DOFs). For each size the script writes

  * an isospring case file, run as `isospring analyze CASE -o OUT --solver cg` (block-Jacobi
    CG, stopping at ||f - K u|| / ||f|| < 1e-10), timings read from report.json;
  * a G+Smo XML file (a single degree-2 patch, its west side clamped, the body force as the
    source function), run by G+Smo's own linear elasticity example
    (examples/linear_elasticity_example.cpp) with the Lame constants of the same steel and
    `-r` refinements (the example refines once more after reading them: 2^(r+1) elements per
    direction); its printed setup, assembly and solver seconds and DOFs are read back. The
    example solves with Eigen's diagonally preconditioned CG at Eigen's default tolerance
    (machine epsilon) and does not print its iterations.

It prints one table: free DOFs of both (they must agree: the same space, the same supports),
assembly seconds, solver seconds, isospring's CG iterations, and the ratios G+Smo / isospring.

The script builds nothing and downloads nothing: --gismo-example is the path of the example's
executable from a G+Smo build of your own; --isospring that of isospring (default:
build/apps/isospring). Both run with OMP_NUM_THREADS = --threads (default 2).

    python3 bench/gismo_compare.py --gismo-example PATH [--sizes 8 16 32] [--threads 2]
"""
import argparse
import json
import math
import os
import re
import subprocess
import sys
import tempfile
import time

E, NU, DENSITY, GRAVITY = 210e9, 0.3, 7800.0, 9.81
LAMBDA = E * NU / ((1 + NU) * (1 - 2 * NU))
MU = E / (2 * (1 + NU))


def gismo_xml(path):
    """The unit cube as one degree-2 patch with one element; side 1 (u = 0, x = 0) clamped."""
    coefs = "\n".join(f"{0.5 * i} {0.5 * j} {0.5 * k}"
                      for k in range(3) for j in range(3) for i in range(3))
    basis = "\n".join(
        f'<Basis index="{d}" type="BSplineBasis">'
        '<KnotVector degree="2" format="ASCII">0 0 0 1 1 1</KnotVector></Basis>'
        for d in range(3))
    force = DENSITY * GRAVITY
    text = f"""<xml>
<MultiPatch id="0" parDim="3">
<patches type="id_range">100 100</patches>
<boundary name="clamped">100 1</boundary>
</MultiPatch>
<Geometry id="100" type="TensorBSpline3">
<Basis type="TensorBSplineBasis3">{basis}</Basis>
<coefs format="ASCII" geoDim="3">{coefs}</coefs>
</Geometry>
<Function type="FunctionExpr" id="1" dim="3">
<c index="0">0</c><c index="1">0</c><c index="2">-{force!r}</c>
</Function>
<boundaryConditions multipatch="0" id="2">
<Function type="FunctionExpr" dim="3" index="0"><c index="0">0</c><c index="1">0</c><c index="2">0</c></Function>
<bc type="Dirichlet" function="0" unknown="0" name="clamped"/>
</boundaryConditions>
<Function type="FunctionExpr" id="3" dim="3"><c index="0">0</c><c index="1">0</c><c index="2">0</c></Function>
</xml>
"""
    with open(path, "w") as f:
        f.write(text)


def isospring_case(path, n):
    case = {
        "schema_version": 1,
        "name": f"cube{n}_p2",
        "units": "SI",
        "geometry": {"type": "box", "size": [1.0, 1.0, 1.0]},
        "discretization": {"degree": [2, 2, 2], "elements": [n, n, n]},
        "material": {"E": E, "nu": NU, "density": DENSITY},
        "boundary": [{"side": "u0", "fix": ["x", "y", "z"]}],
        "load_cases": [{"id": "gravity", "gravity": [0, 0, -GRAVITY]}],
        "output": {"vtk_samples": 0},
    }
    with open(path, "w") as f:
        json.dump(case, f)


def run(command, env):
    start = time.monotonic()
    done = subprocess.run(command, env=env, capture_output=True, text=True)
    wall = time.monotonic() - start
    if done.returncode != 0:
        sys.exit(f"gismo_compare: {' '.join(command)} failed ({done.returncode}):\n"
                 f"{done.stdout[-2000:]}\n{done.stderr[-2000:]}")
    return done.stdout, wall


def run_gismo(example, xml, n, env):
    refinements = int(round(math.log2(n))) - 1
    if 2 ** (refinements + 1) != n or refinements < 0:
        sys.exit(f"gismo_compare: size {n} is not a power of two >= 2 (the example halves "
                 "every element per refinement)")
    out, wall = run([example, "-f", xml, "-r", str(refinements), "-L", repr(LAMBDA),
                     "-M", repr(MU)], env)

    def number(label):
        match = re.search(label + r":\s*([0-9.eE+-]+)", out)
        if not match:
            sys.exit(f"gismo_compare: no '{label}' in the output of {example}:\n{out[-2000:]}")
        return float(match.group(1))

    return {"dofs": int(number("Number of degrees of freedom")), "setup": number("Setup"),
            "assembly": number("Assembly"), "solve": number("Solving"), "wall": wall}


def run_isospring(binary, case, n, out_dir, env):
    _, wall = run([binary, "analyze", case, "-o", out_dir, "--solver", "cg"], env)
    with open(os.path.join(out_dir, "report.json")) as f:
        report = json.load(f)
    load = report["load_cases"][0]
    # All DOFs less the clamped side's (n + 2)^2 control points, as G+Smo counts them.
    return {"dofs": report["dofs"] - 3 * (n + 2) ** 2, "assembly": report["assembly_seconds"],
            "solve": report["factorization_seconds"] + load["solve_seconds"],
            "iterations": load["iterations"], "wall": wall}


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--gismo-example", required=True,
                        help="G+Smo's linear_elasticity_example executable")
    parser.add_argument("--isospring", default=os.path.join("build", "apps", "isospring"))
    parser.add_argument("--sizes", type=int, nargs="+", default=[8, 16, 32])
    parser.add_argument("--threads", type=int, default=2)
    args = parser.parse_args()
    for path, what in ((args.gismo_example, "--gismo-example"), (args.isospring, "--isospring")):
        if not (os.path.isfile(path) and os.access(path, os.X_OK)):
            sys.exit(f"gismo_compare: {what} {path} is not an executable file")
    env = dict(os.environ, OMP_NUM_THREADS=str(args.threads))
    rows = []
    with tempfile.TemporaryDirectory(prefix="gismo_compare_") as work:
        xml = os.path.join(work, "cube.xml")
        gismo_xml(xml)
        for n in args.sizes:
            case = os.path.join(work, f"cube{n}.json")
            isospring_case(case, n)
            iso = run_isospring(args.isospring, case, n, os.path.join(work, f"out{n}"), env)
            gs = run_gismo(args.gismo_example, xml, n, env)
            rows.append((n, iso, gs))
            print(f"{n}^3 done: isospring {iso['wall']:.1f} s, G+Smo {gs['wall']:.1f} s wall",
                  file=sys.stderr)
    print(f"| cube p = 2 | free DOFs isospring / G+Smo | assembly s isospring / G+Smo (ratio) "
          f"| solver s isospring / G+Smo (ratio) | isospring CG iterations | wall s isospring / "
          f"G+Smo |")
    print("|---|---|---|---|---|---|")
    for n, iso, gs in rows:
        print(f"| {n}^3 | {iso['dofs']} / {gs['dofs']} "
              f"| {iso['assembly']:.3f} / {gs['assembly']:.3f} ({gs['assembly'] / iso['assembly']:.1f} x) "
              f"| {iso['solve']:.3f} / {gs['solve']:.3f} ({gs['solve'] / iso['solve']:.1f} x) "
              f"| {iso['iterations']} | {iso['wall']:.2f} / {gs['wall']:.2f} |")


if __name__ == "__main__":
    main()
