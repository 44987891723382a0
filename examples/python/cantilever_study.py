"""A refinement study of the Timoshenko cantilever from Python, cell by cell as in a notebook.

    PYTHONPATH=build/python python3 examples/python/cantilever_study.py OUTDIR

reads examples/timoshenko_beam.json, solves it at degrees 2 and 3 on four meshes, compares the
tip deflection with the closed form (Timoshenko & Goodier) and writes OUTDIR/tip_deflection.csv
and, when matplotlib is installed, OUTDIR/tip_deflection.png. It doubles as a test (CTest:
Python.Example): it exits 1 unless degree 3 reproduces the exact cubic solution and degree 2
converges at least at its L2 rate p + 1 = 3.
"""
import json
import os
import sys

import numpy as np

import isospring

here = os.path.dirname(os.path.abspath(__file__))
out = sys.argv[1] if len(sys.argv) > 1 else "cantilever-study"
os.makedirs(out, exist_ok=True)

# %% The shipped case, and the closed-form tip deflection of its beam (plane stress, end shear P,
# exact clamp): v(L, 0) = -P L^3 / (3 E I) - P (4 + 5 nu) D^2 L / (24 E I), I = D^3 / 12.
with open(os.path.join(here, "..", "timoshenko_beam.json")) as f:
    document = json.load(f)
P, L, D = (document["analytic"][k] for k in ("load", "length", "depth"))
E, nu = document["material"]["E"], document["material"]["nu"]
inertia = D ** 3 / 12
exact = -P * L ** 3 / (3 * E * inertia) - P * (4 + 5 * nu) * D ** 2 * L / (24 * E * inertia)
print(f"exact tip deflection: {exact:.12g} m")

# %% One case file per discretisation (the reader validates and discretises it), one solve each.
rows = []
for degree in (2, 3):
    for n in (2, 4, 8, 16):
        document["discretization"] = {"degree": degree, "elements": [4 * n, n]}
        path = os.path.join(out, f"beam_p{degree}_n{n}.json")
        with open(path, "w") as f:
            json.dump(document, f)
        case = isospring.read_case(path)
        result = isospring.analyze(case)
        tip = isospring.field(case, result["end_shear"], 0, np.array([[1.0, 0.5]]))
        v = tip["displacement"][0, 1]
        rows.append((degree, 4 * n, result.dofs, v, abs(v - exact) / abs(exact)))
        print(f"p = {degree}, {4 * n:3d} x {n:2d} elements, {result.dofs:5d} DOFs: "
              f"v = {v:.12g}, relative error {rows[-1][-1]:.3g}")

# %% The table, and a plot when matplotlib is there.
with open(os.path.join(out, "tip_deflection.csv"), "w") as f:
    f.write("degree,elements_x,dofs,tip_deflection,relative_error\n")
    for r in rows:
        f.write(",".join(f"{x:.17g}" if isinstance(x, float) else str(x) for x in r) + "\n")
try:
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, ax = plt.subplots(figsize=(5, 4))
    for degree in (2, 3):
        data = [(r[2], max(r[4], 1e-16)) for r in rows if r[0] == degree]
        ax.loglog(*zip(*data), "o-", label=f"p = {degree}")
    ax.set_xlabel("DOFs")
    ax.set_ylabel("relative tip deflection error")
    ax.legend()
    fig.tight_layout()
    fig.savefig(os.path.join(out, "tip_deflection.png"), dpi=120)
    print(f"wrote {out}/tip_deflection.csv and tip_deflection.png")
except ImportError:
    print(f"wrote {out}/tip_deflection.csv (no plot: matplotlib is not installed)")

# %% What the theory says: the exact field is a cubic polynomial, so p = 3 reproduces it to
# round-off; p = 2 converges, halving the element size divides the error by at least 2^3.
cubic = [r[4] for r in rows if r[0] == 3]
quadratic = [r[4] for r in rows if r[0] == 2]
ok = max(cubic) < 1e-9 and all(b < a / 8 for a, b in zip(quadratic, quadratic[1:]))
print("checks:", "passed" if ok else "FAILED")
sys.exit(0 if ok else 1)
