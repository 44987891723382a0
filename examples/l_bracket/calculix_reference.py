#!/usr/bin/env python3
"""Independent reference for the CAx-IF L-bracket: gmsh meshes the STEP part (quadratic tetrahedra
on the exact CAD geometry), CalculiX solves it, at several mesh sizes; the displacements of the
loaded end's corners are written with the mesh sizes so that the convergence can be read.

Nothing of isospring is used: the mesh comes from the STEP file through gmsh's own OpenCascade
reader, the solver is CalculiX (C3D10), the loads are consistent nodal forces of a uniform
traction on the end face (midside nodes of a 6-node triangle carry A/3 each, corners 0).

Units: the part is in mm; E in MPa, tractions in MPa, displacements in mm (written in m).

Usage: calculix_reference.py STEP OUT.json [h1 h2 ...]   (gmsh and ccx on PATH)
"""
import json
import os
import subprocess
import sys
import tempfile
import time

E_MPA, NU = 210000.0, 0.3
# The loaded end is the short leg's end face x = 50 mm; the clamped end the long leg's end y = 60.
LOADS = {"shear_y": (0.0, -1.0, 0.0), "shear_z": (0.0, 0.0, 1.0)}  # traction [MPa]
CORNERS = [(50.0, 0.0, 0.0), (50.0, 10.0, 0.0), (50.0, 0.0, 100.0), (50.0, 10.0, 100.0)]


def read_inp(path):
    nodes, tets, section = {}, [], None
    for line in open(path):
        line = line.strip()
        if not line or line.startswith("**"):
            continue
        if line.startswith("*"):
            head = line.upper().replace(" ", "")
            section = "node" if head.startswith("*NODE") else (
                "tet" if head.startswith("*ELEMENT") and "TYPE=C3D10" in head else None)
            continue
        fields = [f for f in line.split(",") if f.strip()]
        if section == "node":
            nodes[int(fields[0])] = tuple(float(f) for f in fields[1:4])
        elif section == "tet":
            tets.append([int(f) for f in fields[1:11]])
    return nodes, tets


def face_loads(nodes, tets, x_face, traction):
    """Consistent nodal forces of a uniform traction on the tets' faces lying on x = x_face."""
    # C3D10 faces (corner, corner, corner, mid, mid, mid), 0-based local numbering.
    faces = [(0, 1, 2, 4, 5, 6), (0, 1, 3, 4, 8, 7), (1, 2, 3, 5, 9, 8), (0, 2, 3, 6, 9, 7)]
    forces, area = {}, 0.0
    for t in tets:
        for f in faces:
            ids = [t[i] for i in f]
            if all(abs(nodes[i][0] - x_face) < 1e-6 for i in ids):
                a, b, c = (nodes[i] for i in ids[:3])
                cross = ((b[1] - a[1]) * (c[2] - a[2]) - (b[2] - a[2]) * (c[1] - a[1]))
                A = abs(cross) / 2.0
                area += A
                for m in ids[3:]:
                    fx = forces.setdefault(m, [0.0, 0.0, 0.0])
                    for k in range(3):
                        fx[k] += traction[k] * A / 3.0
    return forces, area


def solve(step, h, work):
    mesh = os.path.join(work, "mesh.inp")
    subprocess.run(["gmsh", "-3", "-order", "2", "-clmax", str(h), "-clmin", str(h / 4), "-optimize_ho",
                    step, "-format", "inp", "-o", mesh], check=True, stdout=subprocess.DEVNULL)
    nodes, tets = read_inp(mesh)
    clamped = [i for i, x in nodes.items() if abs(x[1] - 60.0) < 1e-6]
    corner_ids = []
    for c in CORNERS:
        best = min(nodes, key=lambda i: sum((nodes[i][k] - c[k]) ** 2 for k in range(3)))
        assert sum((nodes[best][k] - c[k]) ** 2 for k in range(3)) < 1e-12, c
        corner_ids.append(best)
    result = {"h_mm": h, "nodes": len(nodes), "tets": len(tets), "load_cases": {}}
    for name, traction in LOADS.items():
        forces, area = face_loads(nodes, tets, 50.0, traction)
        assert abs(area - 10.0 * 100.0) < 1e-6 * 1000.0, area
        deck = os.path.join(work, name + ".inp")
        with open(deck, "w") as out:
            out.write("*NODE\n")
            for i, x in nodes.items():
                out.write("%d,%.13g,%.13g,%.13g\n" % (i, *x))  # ccx: fields <= 20 chars
            out.write("*ELEMENT,TYPE=C3D10,ELSET=ALL\n")
            for e, t in enumerate(tets, 1):
                out.write("%d,%s\n" % (e, ",".join(str(i) for i in t)))
            out.write("*NSET,NSET=CLAMP\n")
            for i in clamped:
                out.write("%d,\n" % i)
            out.write("*NSET,NSET=CORNERS\n%s\n" % ",".join(str(i) for i in corner_ids))
            out.write("*MATERIAL,NAME=STEEL\n*ELASTIC\n%.13g,%.13g\n" % (E_MPA, NU))
            out.write("*SOLID SECTION,ELSET=ALL,MATERIAL=STEEL\n")
            out.write("*STEP\n*STATIC\n*BOUNDARY\nCLAMP,1,3\n*CLOAD\n")
            for i, f in forces.items():
                for k in range(3):
                    if f[k] != 0.0:
                        out.write("%d,%d,%.13g\n" % (i, k + 1, f[k]))
            out.write("*NODE PRINT,NSET=CORNERS\nU\n*EL PRINT,ELSET=ALL,TOTALS=ONLY\nELSE\n"
                      "*END STEP\n")
        start = time.time()
        subprocess.run(["ccx", "-i", os.path.join(work, name)], cwd=work, check=True,
                       stdout=subprocess.DEVNULL)
        seconds = time.time() - start
        disp, energy, section = {}, None, None
        lines = open(os.path.join(work, name + ".dat")).read().splitlines()
        for line in lines:
            parts = line.split()
            text = line.strip()
            if text.startswith("displacements"):
                section = "u"
            elif text.startswith("total internal energy") or text.startswith("total energy"):
                section = "e"
            elif section == "u" and len(parts) == 4 and parts[0].isdigit():
                disp[int(parts[0])] = [float(v) * 1e-3 for v in parts[1:]]  # mm -> m
            elif section == "e" and len(parts) == 1:
                energy = float(parts[0]) * 1e-3  # N mm -> J
                section = None
        if energy is None:
            raise SystemExit("%s: no total internal energy" % name)
        result["load_cases"][name] = {
            "traction_Pa": [t * 1e6 for t in traction],
            "ccx_seconds": seconds,
            "strain_energy_J": energy,
            "corners": [{"at_m": [c * 1e-3 for c in CORNERS[k]], "u_m": disp[corner_ids[k]]}
                        for k in range(len(CORNERS))]}
    return result


def main():
    step, out = sys.argv[1], sys.argv[2]
    sizes = [float(h) for h in sys.argv[3:]] or [8.0, 4.0, 2.0]
    runs = []
    for h in sizes:
        with tempfile.TemporaryDirectory() as work:
            runs.append(solve(os.path.abspath(step), h, work))
            print("h = %g mm: %d nodes, %d C3D10" % (h, runs[-1]["nodes"], runs[-1]["tets"]),
                  flush=True)
    ref = {"part": os.path.basename(step), "material": {"E_Pa": E_MPA * 1e6, "nu": NU},
           "clamped": "face y = 0.06 m (all components)",
           "loaded": "face x = 0.05 m, uniform traction", "solver": "CalculiX C3D10, gmsh mesh",
           "runs": runs}
    tmp = out + ".tmp"
    with open(tmp, "w") as f:
        json.dump(ref, f, indent=1)
    os.replace(tmp, out)


if __name__ == "__main__":
    main()
