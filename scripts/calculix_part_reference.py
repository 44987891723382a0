#!/usr/bin/python3
"""CalculiX references for third-party STEP parts clamped on one face and loaded by gravity.

For every part of PARTS.json (tests/data/parts/parts.json) gmsh meshes the STEP file (its own
OpenCascade reader, second-order tetrahedra, C3D10), the nodes of the clamped face (gmsh's
surface tag = the face's 0-based index + 1, the order OpenCascade's explorer gives, which is
the numbering of `isospring info`; the face's area is written so that a reader can check it)
are held in x, y and z, gravity acts on every element (*DLOAD GRAV), and CalculiX solves it.
The mesh is graded towards the clamped face, its outline and every re-entrant (concave) edge of
the B-rep (where the stresses are singular), all sizes in proportion to h, and refined (h divided
by `refine`, default 1.4) until the Richardson limits (f = f_inf + C x^q, x = DOFs^(-1/3), q
observed) of the largest nodal displacement and of the strain energy (sum of CalculiX's element
energies ELSE) fitted to the last three meshes agree with the fit to the three before (rates
within 25 %) and lie within `tolerance` (0.2 %) of the last mesh's values, or until the next mesh
would exceed `max_nodes`. With `nested` (true) the meshes are instead one linear mesh of size
`h_m` split uniformly 0, 1, 2, ... times (sizes exactly h, h/2, h/4; new boundary nodes on the
CAD faces) and made quadratic: such a sequence has no scatter from remeshing, and the reference
is the Richardson limit of the last three levels with their observed rate, its error Roache's
grid convergence index 1.25 |f_last / f_inf - 1|. Each part's reference (the limits, or the
last mesh when none converged), its estimated error, mesh sizes, DOFs, the mesh's volume against
OpenCascade's and the whole history go to OUT.json (written atomically after every mesh;
--resume continues a history of the same problem and mesh rule). Nothing of isospring is used.

Units: SI throughout (gmsh reads the STEP file in metres).

Usage: calculix_part_reference.py [--resume] PARTS.json OUT.json [part names...]   (gmsh module, ccx on PATH)
"""
import json
import math
import os
import subprocess
import sys
import tempfile
import time

import gmsh

# gmsh's 10-node tetrahedron numbers its last two midside nodes (2,3), (1,3); CalculiX's C3D10
# (Abaqus) numbers them (1,3), (2,3).
GMSH_TO_C3D10 = [0, 1, 2, 3, 4, 5, 6, 7, 9, 8]
C3D10_EDGES = [(0, 1), (1, 2), (2, 0), (0, 3), (1, 3), (2, 3)]


def generate_with_retries(h, fields, optimise):
    """Meshes at size h. gmsh's meshing or its untangling of curved elements can fail on one mesh
    and succeed on a slightly different one: retry with the sizes 3 % smaller. Returns the h
    used."""
    for attempt in range(4):
        try:
            gmsh.model.mesh.generate(3)
            if not optimise and mesh_volume()[1] > 0:
                gmsh.model.mesh.optimize("HighOrderElastic")
                gmsh.model.mesh.optimize("HighOrder")
            return h
        except Exception:  # gmsh raises a bare Exception
            if attempt == 3:
                raise
            gmsh.model.mesh.clear()
            h *= 0.97
            gmsh.option.setNumber("Mesh.MeshSizeMax", h)
            for f, fraction in fields:
                gmsh.model.mesh.field.setNumber(f, "SizeMin", fraction * h)
                gmsh.model.mesh.field.setNumber(f, "SizeMax", h)
    return h


def generate_nested(level, optimise):
    """The linear mesh split `level` times, then made quadratic. Each split halves every edge
    (a tetrahedron becomes eight), and gmsh places the new nodes of boundary edges on the CAD
    faces, so the meshes of successive levels are nested up to that projection and their sizes
    are exactly h / 2^level: the errors then follow C (h / 2^level)^q without the scatter that
    independent meshes of similar sizes have (Richardson). No retry with other sizes, which
    would break the nesting."""
    gmsh.option.setNumber("Mesh.ElementOrder", 1)
    gmsh.model.mesh.generate(3)
    for _ in range(level):
        gmsh.model.mesh.refine()
    gmsh.model.mesh.setOrder(2)
    if optimise or mesh_volume()[1] > 0:
        gmsh.model.mesh.optimize("HighOrderElastic")
        try:
            gmsh.model.mesh.optimize("HighOrder")
        except Exception:  # gmsh raises a bare Exception
            # It raises when some element's scaled Jacobian stays below its target; the mesh is
            # still usable when no Jacobian at a Gauss point is nonpositive (what CalculiX
            # refuses). Where some stay nonpositive, those elements' midside nodes go back onto
            # their straight edges (no retry with other sizes, which would break the nesting).
            if mesh_volume()[1] > 0:
                straightened = straighten_inverted()
                if straightened is not None:
                    return straightened
                # The untangling moved some vertices too far: the same mesh again (gmsh meshes
                # the same model with the same sizes alike), straightened without it.
                gmsh.model.mesh.clear()
                gmsh.model.mesh.generate(3)
                for _ in range(level):
                    gmsh.model.mesh.refine()
                gmsh.model.mesh.setOrder(2)
                straightened = straighten_inverted()
                if straightened is None:
                    raise SystemExit("tetrahedra stay inverted with straight edges: their "
                                     "vertices are, so the mesh cannot be used")
                return straightened
    return 0


# gmsh's 10-node tetrahedron: its midside nodes 4..9 on these edges of the vertices 0..3.
GMSH_TET10_EDGES = [(0, 1), (1, 2), (2, 0), (0, 3), (2, 3), (1, 3)]


def straighten_inverted(passes=30):
    """Moves the midside nodes of every curved tetrahedron with a nonpositive Jacobian at a
    Gauss point to the middle of their straight edges, where gmsh could not untangle them; a
    tetrahedron with straight edges is valid whenever its vertices are. Their neighbours share
    those nodes, so it repeats until none is left. The part's boundary there becomes the chord
    of the CAD face, a geometric error of order h^2 over those few elements, which
    `mesh_volume_error` shows. Returns the number of nodes moved, or None when a tetrahedron
    stays inverted with straight edges: then its vertices are (on the housing, whose split linear
    mesh was valid before gmsh's untangling ran)."""
    local, weights = gmsh.model.mesh.getIntegrationPoints(11, "Gauss4")
    n = len(weights)
    moved = set()
    for _ in range(passes):
        _, connectivity = gmsh.model.mesh.getElementsByType(11)
        _, determinants, _ = gmsh.model.mesh.getJacobians(11, local)
        bad = [e for e in range(len(determinants) // n) if min(determinants[n * e:n * e + n]) <= 0]
        if not bad:
            return len(moved)
        before = len(moved)
        for e in bad:
            g = [int(t) for t in connectivity[10 * e:10 * e + 10]]
            for k, (a, b) in enumerate(GMSH_TET10_EDGES):
                pa, pb = gmsh.model.mesh.getNode(g[a])[0], gmsh.model.mesh.getNode(g[b])[0]
                gmsh.model.mesh.setNode(g[4 + k], [0.5 * (pa[i] + pb[i]) for i in range(3)], [])
                moved.add(g[4 + k])
        if len(moved) == before:
            return None
    return None


def mesh_part(step, h, clamp_face, part, level=0):
    """Nodes {tag: xyz}, C3D10 connectivity, clamped node tags and the clamped face's area.
    With `nested`, the linear mesh of size h is split uniformly `level` times (every edge halved,
    new boundary nodes on the CAD faces) before the midside nodes are added."""
    gmsh.clear()
    gmsh.option.setString("Geometry.OCCTargetUnit", "M")
    gmsh.model.occ.importShapes(step)
    close_faces_into_a_solid(step)
    place(part)
    gmsh.model.occ.synchronize()
    volumes = gmsh.model.getEntities(3)
    if len(volumes) != 1:
        raise SystemExit("%s: %d solids, expected one" % (step, len(volumes)))
    clamp_refine = part.get("clamp_refine", 3.0)
    edge_refine = part.get("edge_refine", 10.0)
    fields = []

    def refine_near(dim, tags, size, distance_max):
        """Element size `size` at the entities, growing linearly to h over `distance_max`."""
        distance = gmsh.model.mesh.field.add("Distance")
        gmsh.model.mesh.field.setNumbers(distance, "SurfacesList" if dim == 2 else "CurvesList",
                                         tags)
        gmsh.model.mesh.field.setNumber(distance, "NumPointsPerCurve",
                                        max(20, int(10 * edge_refine)))
        threshold = gmsh.model.mesh.field.add("Threshold")
        gmsh.model.mesh.field.setNumber(threshold, "InField", distance)
        gmsh.model.mesh.field.setNumber(threshold, "SizeMin", size)
        gmsh.model.mesh.field.setNumber(threshold, "SizeMax", h)
        gmsh.model.mesh.field.setNumber(threshold, "DistMin", size / 2)
        gmsh.model.mesh.field.setNumber(threshold, "DistMax", distance_max)
        fields.append((threshold, size / h))

    # The clamp's edges are singular (a clamped face meeting a free one: the stress grows like a
    # negative power of the distance from them). The mesh is graded towards those edges
    # (elements `edge_refine` times smaller there, growing linearly to h over 3 h) and is
    # `clamp_refine` times finer over the clamped face, so that the error of the singularity
    # falls with h like the rest. All sizes scale with h (the curvature rule too), so the meshes
    # of a refinement sequence are alike and the error behaves like C h^q (Richardson).
    edges = [abs(tag) for _, tag in
             gmsh.model.getBoundary([(2, clamp_face + 1)], combined=False, oriented=False)]
    refine_near(2, [clamp_face + 1], h / clamp_refine, 4 * h)
    # Re-entrant (concave) edges anywhere on the part are singular as well (the stress grows
    # like r^(lambda - 1), lambda < 1), so they are graded like the clamp's outline, or by their
    # own factor `concave_refine` where the two singularities weigh differently (a clamp whose
    # outline carries the load's whole moment beside a slot that only a small part hangs on).
    concave = []
    if part.get("refine_concave", True):
        concave = [e for e in concave_edges() if e not in edges]
        if "concave_refine" not in part:
            edges, concave = sorted(set(edges) | set(concave)), []
    # `edge_power` > 0 shrinks the singular edges' elements faster than h: h / edge_refine times
    # (h / h_m)^edge_power, so that their error, which falls only like h^(2 lambda) under a fixed
    # grading, falls about as fast as the smooth part's.
    edge_size = h / edge_refine * (h / part["h_m"]) ** part.get("edge_power", 0)
    # `edge_distance` (default 3): the distance, in units of h, over which the edges' elements
    # grow to h. A short one keeps a fine grading at the edges affordable (element size about
    # edge_size + r / edge_distance at distance r), which nested meshes, whose grading refinement
    # does not sharpen, need where the edges' singularity dominates the error.
    refine_near(1, edges, edge_size, part.get("edge_distance", 3) * h)
    concave_size = edge_size * edge_refine / part.get("concave_refine", edge_refine)
    if concave:
        refine_near(1, concave, concave_size, part.get("edge_distance", 3) * h)
    smallest = gmsh.model.mesh.field.add("Min")
    gmsh.model.mesh.field.setNumbers(smallest, "FieldsList", [f for f, _ in fields])
    gmsh.model.mesh.field.setAsBackgroundMesh(smallest)
    gmsh.option.setNumber("Mesh.MeshSizeMax", h)
    gmsh.option.setNumber("Mesh.MeshSizeMin", min([edge_size] + ([concave_size] if concave else [])) / 2)
    # Elements per 2 pi of curvature (`curvature` at the part's first mesh size, default 12), in
    # proportion to 1 / h.
    gmsh.option.setNumber("Mesh.MeshSizeFromCurvature",
                          round(part.get("curvature", 12) * part["h_m"] / h))
    gmsh.option.setNumber("Mesh.ElementOrder", 2)
    # Midside nodes on the straight edges (`straight_midside`) where gmsh cannot untangle the
    # curved ones (t20's B-spline nut): a geometric error of order h^2 that refinement removes.
    gmsh.option.setNumber("Mesh.SecondOrderLinear", 1 if part.get("straight_midside") else 0)
    # Midside nodes go onto the curved geometry; gmsh's untangling of curved elements (elastic
    # analogy plus optimisation: four times the CPU of the mesh itself on the screw) runs only
    # when a curved element has a nonpositive Jacobian at a Gauss point, or always
    # (`high_order_optimize`).
    optimise = part.get("high_order_optimize", False)
    gmsh.option.setNumber("Mesh.HighOrderOptimize", 2 if optimise else 0)
    straightened = 0
    if part.get("nested"):
        straightened = generate_nested(level, optimise)
    else:
        h = generate_with_retries(h, fields, optimise)
    tags, coords, _ = gmsh.model.mesh.getNodes()
    nodes = {int(t): (coords[3 * i], coords[3 * i + 1], coords[3 * i + 2])
             for i, t in enumerate(tags)}
    _, connectivity = gmsh.model.mesh.getElementsByType(11)  # 10-node tetrahedra
    tets = []
    for e in range(len(connectivity) // 10):
        g = [int(n) for n in connectivity[10 * e:10 * e + 10]]
        tets.append([g[k] for k in GMSH_TO_C3D10])
    check_midside_nodes(nodes, tets)
    face = clamp_face + 1
    clamped, _, _ = gmsh.model.mesh.getNodes(2, face, includeBoundary=True)
    area = gmsh.model.occ.getMass(2, face)
    volume, inverted = mesh_volume()
    exact = gmsh.model.occ.getMass(3, volumes[0][1])
    geometry = {"mesh_volume_error": volume / exact - 1, "inverted_gauss_points": inverted,
                "refined_edges": len(edges) + len(concave)}
    if straightened:
        geometry["straightened_midside_nodes"] = straightened
    return nodes, tets, sorted(int(t) for t in clamped), area, h, geometry


def close_faces_into_a_solid(step):
    """A file of faces without a solid (a closed shell in a surface model) is closed into one, as
    isospring's reader does (sewn, then made a solid): the surfaces keep their tags, so face i is
    still gmsh's surface i + 1 (checked by their centres of mass)."""
    if gmsh.model.occ.getEntities(3):
        return
    surfaces = [tag for _, tag in gmsh.model.occ.getEntities(2)]
    centres = {tag: gmsh.model.occ.getCenterOfMass(2, tag) for tag in surfaces}
    loop = gmsh.model.occ.addSurfaceLoop(surfaces, sewing=True)
    gmsh.model.occ.addVolume([loop])
    after = {tag: gmsh.model.occ.getCenterOfMass(2, tag)
             for _, tag in gmsh.model.occ.getEntities(2)}
    if after.keys() != centres.keys() or any(
            max(abs(a - b) for a, b in zip(after[t], centres[t])) > 1e-12 for t in surfaces):
        raise SystemExit("%s: closing the faces into a solid renumbered them" % step)


def place(part):
    """`placement` ({"axis": [x, y, z], "angle_deg": a}): the part turned rigidly by a degrees
    about the axis through the origin (right hand), before it is meshed. OpenCascade transforms
    the shape in place, so the faces keep their tags (the clamped face's area, compared with the
    immersed quadrature's in the test, confirms it)."""
    placement = part.get("placement")
    if placement is None:
        return
    axis = placement["axis"]
    if len(axis) != 3 or sum(c * c for c in axis) == 0:
        raise SystemExit("%s: placement axis must be three numbers, not all zero" % part["name"])
    gmsh.model.occ.rotate(gmsh.model.occ.getEntities(3), 0, 0, 0, *axis,
                          math.radians(placement["angle_deg"]))


def _unit(a):
    n = sum(x * x for x in a) ** 0.5
    return [x / n for x in a]


def _into_face(surface, point, tangent, normal):
    """The unit direction from an edge point into the face `surface` (normal to the edge), or
    None. Of the two candidates the one whose nearby point (a few steps tried, since the trim
    test has a tolerance) lies inside the trimmed face and the other's not."""
    d = _unit([tangent[1] * normal[2] - tangent[2] * normal[1],
               tangent[2] * normal[0] - tangent[0] * normal[2],
               tangent[0] * normal[1] - tangent[1] * normal[0]])
    for step in (1e-4, 3e-4, 3e-5):  # metres
        inside = []
        for sign in (1, -1):
            q = [point[i] + sign * step * d[i] for i in range(3)]
            try:
                uv = gmsh.model.getParametrization(2, surface, q)
                inside.append(gmsh.model.isInside(2, surface, list(uv)) > 0)
            except Exception:  # gmsh raises a bare Exception when the inverse mapping fails
                inside.append(False)
        if inside == [True, False]:
            return d
        if inside == [False, True]:
            return [-x for x in d]
    return None


def concave_edges(threshold=0.05):
    """Tags of the B-rep edges where the solid is re-entrant (interior dihedral angle above 180
    degrees). At three points of each edge shared by two faces, the direction d_i from the edge
    into face i (normal to the edge, tangent to the face) and face j's outward normal n_j: on a
    convex edge face i turns away from face j's outside (d_i . n_j < 0), on a concave one towards
    it, and on a smooth edge d_i . n_j = 0. gmsh's normals of an imported solid's faces point out
    of the solid (checked on the CAx-IF nut: all its edges come out convex or smooth)."""
    found = []
    for _, curve in gmsh.model.getEntities(1):
        faces = list(gmsh.model.getAdjacencies(1, curve)[0])
        if len(faces) != 2:
            continue
        lo, hi = gmsh.model.getParametrizationBounds(1, curve)
        turns = []
        for fraction in (0.25, 0.5, 0.75):
            t = lo[0] + fraction * (hi[0] - lo[0])
            point = gmsh.model.getValue(1, curve, [t])
            tangent = _unit(gmsh.model.getDerivative(1, curve, [t]))
            normals = [_unit(gmsh.model.getNormal(f, list(gmsh.model.getParametrization(2, f, point))))
                       for f in faces]
            into = [_into_face(f, point, tangent, n) for f, n in zip(faces, normals)]
            if None in into:
                continue
            turns.append(0.5 * (sum(a * b for a, b in zip(into[0], normals[1])) +
                                sum(a * b for a, b in zip(into[1], normals[0]))))
        if turns and min(turns) > threshold:
            found.append(curve)
    return found


def mesh_volume():
    """Volume of the current second-order mesh (Gauss rule exact for the cubic Jacobian) and the
    number of curved tetrahedra with a nonpositive Jacobian at a Gauss point."""
    local, weights = gmsh.model.mesh.getIntegrationPoints(11, "Gauss4")
    _, determinants, _ = gmsh.model.mesh.getJacobians(11, local)
    n = len(weights)
    volume = sum(weights[i % n] * d for i, d in enumerate(determinants))
    return volume, sum(1 for d in determinants if d <= 0)


def check_midside_nodes(nodes, tets):
    """Every midside node lies near the middle of its edge (a wrong node order would not)."""
    for t in tets[:: max(1, len(tets) // 2000)]:
        for k, (a, b) in enumerate(C3D10_EDGES):
            pa, pb, pm = nodes[t[a]], nodes[t[b]], nodes[t[4 + k]]
            length = sum((pa[i] - pb[i]) ** 2 for i in range(3)) ** 0.5
            off = sum((pm[i] - 0.5 * (pa[i] + pb[i])) ** 2 for i in range(3)) ** 0.5
            assert off < 0.3 * length, "C3D10 midside node order"


def write_deck(path, nodes, tets, clamped, part):
    material = part["material"]
    with open(path, "w") as out:
        out.write("*NODE,NSET=NALL\n")
        for i, x in nodes.items():
            out.write("%d,%.13g,%.13g,%.13g\n" % (i, *x))  # ccx reads fields of <= 20 characters
        out.write("*ELEMENT,TYPE=C3D10,ELSET=EALL\n")
        for e, t in enumerate(tets, 1):
            out.write("%d,%s\n" % (e, ",".join(str(i) for i in t)))
        out.write("*NSET,NSET=CLAMP\n")
        for i in clamped:
            out.write("%d,\n" % i)
        out.write("*MATERIAL,NAME=M\n*ELASTIC\n%.15g,%.15g\n*DENSITY\n%.15g\n" %
                  (material["E"], material["nu"], material["density"]))
        out.write("*SOLID SECTION,ELSET=EALL,MATERIAL=M\n")
        g = part["gravity"]
        norm = sum(c * c for c in g) ** 0.5
        out.write("*STEP\n*STATIC\n*BOUNDARY\nCLAMP,1,3\n*DLOAD\n")
        out.write("EALL,GRAV,%.15g,%.15g,%.15g,%.15g\n" % (norm, g[0] / norm, g[1] / norm, g[2] / norm))
        out.write("*NODE PRINT,NSET=NALL\nU\n*EL PRINT,ELSET=EALL,TOTALS=ONLY\nELSE\n*END STEP\n")


def read_results(path):
    """Largest nodal displacement (its node and vector) and the total strain energy."""
    largest, at, vector, energy = -1.0, None, None, None
    section = None
    for line in open(path):
        text = line.strip()
        if text.startswith("displacements"):
            section = "u"
            continue
        if text.startswith("total internal energy") or text.startswith("total energy"):
            section = "e"
            continue
        fields = text.split()
        if section == "u" and len(fields) == 4 and fields[0].isdigit():
            u = [float(v) for v in fields[1:]]
            norm = sum(c * c for c in u) ** 0.5
            if norm > largest:
                largest, at, vector = norm, int(fields[0]), u
        elif section == "e" and len(fields) == 1:
            energy = float(fields[0])
            section = None
    if energy is None:
        raise SystemExit("%s: no total internal energy" % path)
    return largest, at, vector, energy


def solve(part, step, h, work, level=0):
    """One mesh and its CalculiX solution. CalculiX refuses a mesh with a curved element that
    gmsh left inverted (nonpositive Jacobian); such a mesh is made again with the sizes 3 %
    smaller (a different mesh), up to three times (not for nested meshes)."""
    for attempt in range(4):
        start = time.time()
        nodes, tets, clamped, area, h, geometry = mesh_part(step, h, part["clamp_face"], part,
                                                            level)
        mesh_seconds = time.time() - start
        deck = os.path.join(work, "part.inp")
        write_deck(deck, nodes, tets, clamped, part)
        start = time.time()
        run = subprocess.run(["ccx", "-i", "part"], cwd=work, capture_output=True, text=True)
        ccx_seconds = time.time() - start
        if run.returncode == 0:
            break
        errors = [line for line in run.stdout.splitlines() if "ERROR" in line.upper()]
        print("%s: CalculiX failed on h %.4g m (%s); meshing again 3 %% finer" %
              (part["name"], h, errors[0].strip() if errors else "exit %d" % run.returncode),
              flush=True)
        if attempt == 3 or part.get("nested"):
            raise SystemExit("%s: CalculiX failed on %s" %
                             (part["name"], "the nested mesh" if part.get("nested") else
                              "four meshes"))
        h *= 0.97
    largest, node, vector, energy = read_results(os.path.join(work, "part.dat"))
    nested = {"level": level, "relative_size": 0.5 ** level} if part.get("nested") else {}
    return {"h_m": h / 2 ** level, **nested, "nodes": len(nodes), "dofs": 3 * len(nodes),
            "tets": len(tets),
            "clamped_nodes": len(clamped), "clamp_face_area_m2": area,
            "max_displacement_m": largest, "max_displacement_at_m": list(nodes[node]),
            "max_displacement_vector_m": vector, "strain_energy_J": energy,
            "mesh_seconds": mesh_seconds, "ccx_seconds": ccx_seconds, **geometry}


def mesh_size(run):
    """The size x of Richardson's model: h / 2^level, exact for nested meshes; else the mean
    element size DOFs^(-1/3)."""
    return run["relative_size"] if "relative_size" in run else run["dofs"] ** (-1.0 / 3.0)


def richardson(runs, key):
    """The limit of runs[-3:]'s values under f = f_inf + C x^q with x = DOFs^(-1/3), the mean
    element size the meshes actually have (the graded zones, the curvature rule and gmsh's
    retries make it differ from h's ratios), q fitted to the three meshes.

    Returns (f_inf, q, |f_last / f_inf - 1|) or None when the three values do not converge
    monotonically (changes of one sign, shrinking) with a rate between 0.3 and 8."""
    (h0, f0), (h1, f1), (h2, f2) = [(mesh_size(r), r[key]) for r in runs[-3:]]
    d1, d2 = f1 - f0, f2 - f1
    if d1 == 0 or d2 == 0 or (d1 > 0) != (d2 > 0) or abs(d2) >= abs(d1):
        return None

    def ratio(q):  # (f1 - f0) / (f2 - f1) predicted by the model, increasing in q
        return (h0 ** q - h1 ** q) / (h1 ** q - h2 ** q)

    lo, hi = 0.3, 8.0
    if not ratio(lo) <= d1 / d2 <= ratio(hi):
        return None
    for _ in range(100):
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if ratio(mid) < d1 / d2 else (lo, mid)
    q = 0.5 * (lo + hi)
    c = d2 / (h2 ** q - h1 ** q)
    limit = f2 - c * h2 ** q
    return limit, q, abs(f2 / limit - 1)


def stable_limit(runs, key):
    """The Richardson limit of the last three meshes, trusted only when the rate is stable: the
    fit to the three meshes before (one mesh earlier) gives a rate within 25 % and a limit within
    the last mesh's distance from it. Returns (limit, rate, previous rate, error) with error =
    the last mesh's distance from the limit plus the two fits' difference, or None."""
    if len(runs) < 4:
        return None
    now, before = richardson(runs, key), richardson(runs[:-1], key)
    if not now or not before or abs(now[1] / before[1] - 1) > 0.25:
        return None
    spread = abs(before[0] / now[0] - 1)
    if spread > now[2]:
        return None
    return now[0], now[1], before[1], now[2] + spread


def nested_limit(runs, key):
    """For nested meshes (sizes h, h/2, h/4 exactly): the Richardson limit of the last three
    with their observed rate q, and as its error Roache's grid convergence index for three
    grids, 1.25 |f_last / f_inf - 1| (the fine grid's distance from the limit with a safety
    factor; ASME V&V 20). Returns (limit, rate, rate, error) like `stable_limit`, or None when
    the three values do not converge monotonically with a rate between 0.3 and 8."""
    if len(runs) < 3:
        return None
    fit = richardson(runs, key)
    if not fit:
        return None
    return fit[0], fit[1], fit[1], 1.25 * fit[2]


def assess(part, runs):
    """Adds the changes from the previous mesh, the observed rates and (`stable_limit`) the
    Richardson limits to runs[-1]; True when both limits lie within `tolerance` of it."""
    r = runs[-1]
    if len(runs) >= 2:
        prev = runs[-2]
        r["change_max_displacement"] = abs(r["max_displacement_m"] / prev["max_displacement_m"] - 1)
        r["change_strain_energy"] = abs(r["strain_energy_J"] / prev["strain_energy_J"] - 1)
    for key, name in (("max_displacement_m", "max_displacement"),
                      ("strain_energy_J", "strain_energy")):
        fit = richardson(runs, key) if len(runs) >= 3 else None
        if fit:
            r["rate_" + name] = fit[1]
    limit = nested_limit if part.get("nested") else stable_limit
    u = limit(runs, "max_displacement_m")
    e = limit(runs, "strain_energy_J")
    if not (u and e):
        return False
    r["richardson"] = {"max_displacement_m": u[0], "rate_max_displacement": u[1],
                       "previous_rate_max_displacement": u[2], "error_max_displacement": u[3],
                       "strain_energy_J": e[0], "rate_strain_energy": e[1],
                       "previous_rate_strain_energy": e[2], "error_strain_energy": e[3]}
    print("%s: Richardson |u| %.6e m (rates %.2f, %.2f; error %.3f %%), energy %.6e J "
          "(rates %.2f, %.2f; error %.3f %%)" % (part["name"], u[0], u[2], u[1], 100 * u[3],
                                                 e[0], e[2], e[1], 100 * e[3]), flush=True)
    tolerance = part.get("tolerance", 0.002)
    return u[3] < tolerance and e[3] < tolerance


def converge(part, folder, earlier=(), on_mesh=None):
    """Meshes refined by `refine` until the stable Richardson limits (`stable_limit`) of the
    largest displacement and the energy lie within `tolerance` of the last mesh's values (the
    last mesh's estimated error is below it); or until the next mesh would exceed `max_nodes`.
    `earlier`: meshes already solved with the same mesh rule, continued from; `on_mesh(runs)` is
    called after every mesh (the history is written then, so a stopped run keeps it)."""
    step = os.path.join(folder, part["file"])
    refine = part.get("refine", 1.4)
    runs = list(earlier)
    while True:
        if runs:
            if assess(part, runs):
                return runs, True
            growth = 8 if part.get("nested") else refine ** 3
            if runs[-1]["nodes"] * growth > part.get("max_nodes", 150000):
                return runs, False
        nested = part.get("nested", False)
        h = part["h_m"] if nested or not runs else runs[-1]["h_m"] / refine
        with tempfile.TemporaryDirectory() as work:
            runs.append(solve(part, step, h, work, len(runs) if nested else 0))
        assess(part, runs)
        if on_mesh:
            on_mesh(runs)
        r = runs[-1]
        print("%s: h %.4g m, %d DOFs, max |u| %.6e m, energy %.6e J, mesh volume %+.1e "
              "(%.0f + %.0f s)" % (part["name"], r["h_m"], r["dofs"], r["max_displacement_m"],
                                   r["strain_energy_J"], r["mesh_volume_error"],
                                   r["mesh_seconds"], r["ccx_seconds"]), flush=True)


# The keys of parts.json that define a part's problem and its meshes: a reference's history is
# continued only when they are unchanged.
PROBLEM_KEYS = ("file", "clamp_face", "gravity", "material", "h_m", "curvature", "edge_refine",
                "clamp_refine", "edge_power", "refine", "refine_concave", "straight_midside",
                "high_order_optimize", "nested")
OPTIONAL_PROBLEM_KEYS = ("edge_distance", "placement", "concave_refine")


def main():
    resume = "--resume" in sys.argv
    args = [a for a in sys.argv[1:] if a != "--resume"]
    parts_file, out = args[0], args[1]
    chosen = set(args[2:])
    folder = os.path.dirname(os.path.abspath(parts_file))
    parts = json.load(open(parts_file))["parts"]
    old = json.load(open(out)) if os.path.exists(out) else {"parts": {}}
    gmsh.initialize()
    gmsh.option.setNumber("General.Terminal", 0)
    results = dict(old["parts"])
    for part in parts:
        if chosen and part["name"] not in chosen:
            continue
        problem = {k: part.get(k) for k in PROBLEM_KEYS}
        # Options added later join the problem only where set, so that older histories resume.
        problem.update({k: part[k] for k in OPTIONAL_PROBLEM_KEYS if k in part})

        def record(runs, converged=False, part=part, problem=problem):
            results[part["name"]] = summary(part, problem, runs, converged)
            write_reference(out, results)

        earlier = results.get(part["name"], {})
        # With --resume, a history of the same problem and mesh rule is continued.
        if resume and earlier.get("problem") == problem:
            runs, converged = converge(part, folder, earlier["history"], record)
        else:
            runs, converged = converge(part, folder, on_mesh=record)
        record(runs, converged)
    gmsh.finalize()


def summary(part, problem, runs, converged):
    """A part's entry of OUT.json. The reference is the Richardson limit where a stable one exists
    (its error is well below the last mesh's, which `estimated_error` bounds), else the last
    mesh."""
    last = runs[-1]
    limit = last.get("richardson", last)
    return {
        "file": part["file"], "clamp_face": part["clamp_face"], "gravity_m_s2": part["gravity"],
        "material": part["material"], "converged": converged,
        "tolerance": part.get("tolerance", 0.002),
        "reference": "richardson" if "richardson" in last else "last mesh",
        "max_displacement_m": limit["max_displacement_m"],
        "strain_energy_J": limit["strain_energy_J"],
        "estimated_error": max(last.get("richardson", {}).get("error_max_displacement", 1),
                               last.get("richardson", {}).get("error_strain_energy", 1)),
        "h_m": last["h_m"], "dofs": last["dofs"], "problem": problem, "history": runs}


def write_reference(out, results):
    reference = {"solver": "CalculiX %s, C3D10 on gmsh %s meshes" % (ccx_version(), gmsh.__version__),
                 "script": "scripts/calculix_part_reference.py", "parts": results}
    tmp = out + ".tmp"
    with open(tmp, "w") as f:
        json.dump(reference, f, indent=1)
    os.replace(tmp, out)


def ccx_version():
    run = subprocess.run(["ccx", "-v"], capture_output=True, text=True)
    words = (run.stdout + run.stderr).split()
    return words[-1] if words else "?"


if __name__ == "__main__":
    main()
