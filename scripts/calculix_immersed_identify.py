#!/usr/bin/python3
"""Marker data for `isospring identify` on an immersed part, computed by CalculiX on a gmsh mesh
of the same STEP file (nothing of isospring is used).

The part is examples/immersed/rounded_bracket.step, clamped on its face 7 (the plane x = 0,
STEP name 'clamp'; gmsh's surface tag = index + 1, the numbering of `isospring info`), loaded in
two load cases by a body force of density x 20 m/s^2: "side" along +y and "lift" along +z
(*DLOAD GRAV; a traction entered as nodal forces on the end face gave displacements 15 times
the immersed and the beam-theory values, a deck error not found in the time, so the loads are
body forces here). gmsh meshes the part with second-order tetrahedra (C3D10), graded towards the
clamp and the re-entrant edges (calculix_part_reference.mesh_part). Three CalculiX runs (side,
lift, the unit self-weight) give every dataset by superposition (linear elasticity).

Markers: MARKERS nodes per load case drawn (fixed seed) from the mesh's surface nodes off the
clamp; displacements plus Gaussian noise of NOISE (0.2 %) of the dataset's largest marker
displacement. Two datasets:
  markers_weight.csv  every case also carries the part's own weight (g = 9.81 m/s^2 along -z),
                      which the case file does not declare (the hidden effect)
  markers_clean.csv   the declared loads alone
With --check-mesh a mesh 1.4 x coarser is solved too; the change of the displacements between
the two at the B-rep's vertices off the clamp (nodes of both meshes; rms over vertices and
components, relative to the noise) goes to truth.json as the reference's error estimate.

Usage: calculix_immersed_identify.py [--check-mesh] OUT_FOLDER   (gmsh module, ccx on PATH)
"""
import json
import math
import os
import random
import subprocess
import sys
import tempfile
import time

import gmsh

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from calculix_part_reference import mesh_part  # noqa: E402

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
STEP = os.path.join(ROOT, "examples", "immersed", "rounded_bracket.step")
CLAMP_FACE = 7
MATERIAL = {"E": 3.5e9, "nu": 0.36, "density": 1240.0}  # a printed polymer
GRAVITY = 9.81
MARKERS = 30
NOISE = 0.002
SEED = 20261127
CHECK_MESH = "--check-mesh" in sys.argv  # also solve a mesh 1.4 x coarser and compare
PART = {"name": "rounded_bracket", "h_m": 0.0045, "clamp_refine": 2.0, "edge_refine": 4.0,
        "curvature": 12}
ACCELERATION = 20.0  # m/s^2: the load cases' body forces are density x this
CASES = {"side": (0.0, 1.0, 0.0), "lift": (0.0, 0.0, 1.0)}  # directions of the body force


def write_deck(path, nodes, tets, clamped, load):
    with open(path, "w") as out:
        out.write("*NODE,NSET=NALL\n")
        for i, x in nodes.items():
            out.write("%d,%.13g,%.13g,%.13g\n" % (i, *x))
        out.write("*ELEMENT,TYPE=C3D10,ELSET=EALL\n")
        for e, t in enumerate(tets, 1):
            out.write("%d,%s\n" % (e, ",".join(str(i) for i in t)))
        out.write("*NSET,NSET=CLAMP\n")
        for i in clamped:
            out.write("%d,\n" % i)
        out.write("*MATERIAL,NAME=M\n*ELASTIC\n%.15g,%.15g\n*DENSITY\n%.15g\n" %
                  (MATERIAL["E"], MATERIAL["nu"], MATERIAL["density"]))
        out.write("*SOLID SECTION,ELSET=EALL,MATERIAL=M\n*STEP\n*STATIC\n*BOUNDARY\nCLAMP,1,3\n")
        if load == "weight":
            out.write("*DLOAD\nEALL,GRAV,%.15g,0,0,-1\n" % GRAVITY)
        else:
            out.write("*DLOAD\nEALL,GRAV,%.15g,%g,%g,%g\n" % (ACCELERATION, *CASES[load]))
        out.write("*NODE PRINT,NSET=NALL\nU\n*END STEP\n")


def read_displacements(path):
    u, section = {}, False
    for line in open(path):
        text = line.strip()
        if text.startswith("displacements"):
            section = True
            continue
        fields = text.split()
        if section and len(fields) == 4 and fields[0].isdigit():
            u[int(fields[0])] = [float(v) for v in fields[1:]]
    return u


def surface_nodes(clamped):
    """Corner nodes of the surface triangles, off the clamp face."""
    held = set(clamped)
    found = set()
    for _, surface in gmsh.model.getEntities(2):
        if surface == CLAMP_FACE + 1:
            continue
        types, _, connectivity = gmsh.model.mesh.getElements(2, surface)
        for kind, conn in zip(types, connectivity):
            if kind == 9:
                for e in range(len(conn) // 6):
                    found.update(int(v) for v in conn[6 * e:6 * e + 3])
    return sorted(found - held)


def solve_all(h, work):
    """Nodes, surface nodes and the three unit solutions on the mesh of size h."""
    part = dict(PART, h_m=h)
    nodes, tets, clamped, _, h, geometry = mesh_part(STEP, h, CLAMP_FACE, part)
    surface = surface_nodes(clamped)
    # The B-rep's vertices are nodes of every mesh: the two meshes' solutions meet there.
    vertices = {}
    for _, point in gmsh.model.getEntities(0):
        tags, coords, _ = gmsh.model.mesh.getNodes(0, point)
        if len(tags) == 1 and int(tags[0]) not in set(clamped):
            vertices[point] = int(tags[0])
    solutions, seconds = {}, 0.0
    for load in ("side", "lift", "weight"):
        write_deck(os.path.join(work, "part.inp"), nodes, tets, clamped, load)
        start = time.time()
        run = subprocess.run(["ccx", "-i", "part"], cwd=work, capture_output=True, text=True)
        seconds += time.time() - start
        if run.returncode != 0:
            raise SystemExit("CalculiX failed on %s: %s" % (load, run.stdout[-2000:]))
        solutions[load] = read_displacements(os.path.join(work, "part.dat"))
    return {"nodes": nodes, "surface": surface, "vertices": vertices, "u": solutions, "tets": len(tets),
            "ccx_seconds": seconds, "mesh_volume_error": geometry["mesh_volume_error"]}


def main():
    args = [a for a in sys.argv[1:] if a != "--check-mesh"]
    if len(args) != 1:
        raise SystemExit(__doc__)
    out = args[0]
    os.makedirs(out, exist_ok=True)
    gmsh.initialize()
    gmsh.option.setNumber("General.Terminal", 0)
    with tempfile.TemporaryDirectory() as work:
        fine = solve_all(PART["h_m"], work)
        coarse = solve_all(PART["h_m"] * 1.4, work) if CHECK_MESH else None
    rng = random.Random(SEED)
    picks = {case: rng.sample(fine["surface"], MARKERS) for case in CASES}
    truth = {"part": "examples/immersed/rounded_bracket.step", "clamp_face": CLAMP_FACE,
             "material": MATERIAL, "body_force_acceleration": ACCELERATION,
             "load_cases": CASES,
             "hidden_gravity": [0, 0, -GRAVITY], "markers_per_case": MARKERS, "seed": SEED,
             "noise_fraction": NOISE, "meshes": [], "datasets": {}}
    for mesh in (fine, coarse) if coarse else (fine,):
        truth["meshes"].append({ "nodes": len(mesh["nodes"]), "tets": mesh["tets"],
                                "ccx_seconds": mesh["ccx_seconds"],
                                "mesh_volume_error": mesh["mesh_volume_error"]})
    for name, weight in (("weight", 1.0), ("clean", 0.0)):
        rows, values, change = [], [], []
        for case in CASES:
            for node in picks[case]:
                x = fine["nodes"][node]
                u = [fine["u"][case][node][i] + weight * fine["u"]["weight"][node][i]
                     for i in range(3)]
                rows.append((case, x, u))
            for point, node in fine["vertices"].items() if coarse else ():
                other = coarse["vertices"].get(point)
                if other is None:
                    continue
                for i in range(3):
                    change.append(fine["u"][case][node][i] + weight * fine["u"]["weight"][node][i]
                                  - coarse["u"][case][other][i]
                                  - weight * coarse["u"]["weight"][other][i])
                values += u
        sigma = NOISE * max(math.sqrt(sum(c * c for c in r[2])) for r in rows)
        with open(os.path.join(out, "markers_%s.csv.tmp" % name), "w") as f:
            f.write("load_case,x,y,z,ux,uy,uz\n")
            for case, x, u in rows:
                noisy = [c + rng.gauss(0.0, sigma) for c in u]
                f.write("%s,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g\n" % (case, *x, *noisy))
        os.replace(os.path.join(out, "markers_%s.csv.tmp" % name),
                   os.path.join(out, "markers_%s.csv" % name))
        rms_change = math.sqrt(sum(c * c for c in change) / len(change)) if change else None
        truth["datasets"][name] = {
            "noise_sigma_m": sigma, "gravity_in_data": weight == 1.0,
            "vertex_components_compared": len(change),
            "mesh_change_rms_over_noise": rms_change / sigma if rms_change is not None else None}
    gmsh.finalize()
    with open(os.path.join(out, "truth.json.tmp"), "w") as f:
        json.dump(truth, f, indent=1)
    os.replace(os.path.join(out, "truth.json.tmp"), os.path.join(out, "truth.json"))


if __name__ == "__main__":
    main()
