"""Tests of the Python module `isospring` (python/), run by CTest as Python.Module.

Plain asserts, no pytest: `python3 tests/python/test_isospring.py` with PYTHONPATH at the build's
module folder (BUILD/python), ISOSPRING_SOURCE_DIR at the repository and ISOSPRING_EXECUTABLE at
the `isospring` program (CTest sets all three). Every check compares with something computed
independently: closed forms, numpy arithmetic on the patch's own data, finite differences, or the
report the program writes for the same case.
"""
import contextlib
import csv
import io
import json
import math
import os
import subprocess
import sys
import tempfile

import numpy as np

import isospring

SOURCE = os.environ.get("ISOSPRING_SOURCE_DIR",
                        os.path.join(os.path.dirname(__file__), "..", ".."))
EXAMPLES = os.path.join(SOURCE, "examples")
PROGRAM = os.environ.get("ISOSPRING_EXECUTABLE", "isospring")
RNG = np.random.default_rng(17)


def quarter_circle():
    """The rational quadratic quarter circle of radius 1 (The NURBS Book, Ex. 7.1)."""
    w = 1 / math.sqrt(2)
    return isospring.Patch([2], [[0, 0, 0, 1, 1, 1]], np.array([[1, 0, 0], [1, 1, 0], [0, 1, 0.]]),
                           [1, w, 1])


def annulus():
    return isospring.read_patch_file(os.path.join(EXAMPLES, "patches", "quarter_annulus.json"))[0]


def test_circle_is_exact():
    arc = quarter_circle()
    u = np.linspace(0, 1, 201).reshape(-1, 1)
    points, first = arc.derivatives(u)
    assert points.shape == (201, 3) and first.shape == (201, 3, 1)
    assert np.max(np.abs(np.linalg.norm(points, axis=1) - 1)) < 1e-14
    # On a circle the tangent is orthogonal to the radius.
    assert np.max(np.abs(np.einsum("ij,ij->i", points, first[:, :, 0]))) < 1e-13
    # A 1D array is m parameters of a curve, and gives the same points.
    assert np.array_equal(arc.evaluate(np.linspace(0, 1, 201)), points)
    # The ends and the middle (45 degrees) by the closed form.
    assert np.allclose(points[[0, 100, 200]], [[1, 0, 0], [math.sqrt(.5), math.sqrt(.5), 0],
                                               [0, 1, 0]], rtol=0, atol=1e-15)


def test_partition_of_unity_and_evaluation():
    patch = annulus()
    cps = patch.control_points
    for u in RNG.random((50, 2)):
        indices, values, first = patch.basis(list(u))
        assert abs(np.sum(values) - 1) < 1e-14 and np.all(values >= 0)
        # The derivatives of a partition of unity sum to zero.
        assert np.max(np.abs(np.sum(first, axis=0))) < 1e-12
        # evaluate() is sum R_i P_i over the non-zero basis functions.
        assert np.max(np.abs(values @ cps[indices] - patch.evaluate(u)[0])) < 1e-14


def test_derivatives_match_finite_differences():
    patch = annulus()
    h = 1e-6
    for u in RNG.uniform(0.05, 0.95, (20, 2)):
        _, first = patch.derivatives(u)
        for a in range(2):
            step = np.zeros(2)
            step[a] = h
            fd = (patch.evaluate(u + step)[0] - patch.evaluate(u - step)[0]) / (2 * h)
            assert np.max(np.abs(fd - first[0, :, a])) < 1e-8


def test_refinement_keeps_the_geometry():
    patch = annulus()
    fine = isospring.elevate_degree(patch, 2)
    fine = isospring.refine_uniform(fine, 3)
    fine = isospring.insert_knot(fine, 0, 0.3, times=2)
    fine = isospring.refine_knots(fine, 1, [0.25, 0.5])
    fine = isospring.elevate_degree(fine, 1, dir=1)
    assert fine.degrees == [4, 4]
    # u: degree 4, 3 spans + a double knot: 4 + 3 + 2 + 1 = 10; v: 5 spans at degree 4 ... as
    # from the knot vectors themselves: n = len(knots) - p - 1.
    assert fine.shape == [len(k) - p - 1 for k, p in zip(fine.knots, fine.degrees)]
    u = RNG.random((500, 2))
    assert np.max(np.abs(fine.evaluate(u) - patch.evaluate(u))) < 1e-12
    radii = np.linalg.norm(fine.evaluate(np.column_stack([u[:, 0], np.zeros(500)])), axis=1)
    assert np.max(np.abs(radii - 1)) < 1e-13


def test_patch_files_round_trip():
    patch = isospring.refine_uniform(annulus(), 2)
    with tempfile.TemporaryDirectory() as folder:
        path = os.path.join(folder, "fine.json")
        isospring.write_patch_file(path, [patch])
        back = isospring.read_patch_file(path)[0]
    assert back.knots == patch.knots and back.weights == patch.weights
    assert np.array_equal(back.control_points, patch.control_points)


def test_input_errors_are_exceptions():
    try:
        isospring.Patch([2], [[0, 0, 0.5, 1, 1, 1]], np.zeros((3, 3)))
        raise AssertionError("an unclamped knot vector was accepted")
    except isospring.InputError as e:
        assert "clamped" in str(e) and isinstance(e, ValueError)
    with tempfile.TemporaryDirectory() as folder:
        path = os.path.join(folder, "bad.json")
        with open(path, "w") as f:
            f.write('{"patches": [{"degrees": [1], "knots": [[0, 0, 1, 1]], '
                    '"control_points": [[0, 0, 0], [1, 0, 0]], "weight": [1, 1]}]}')
        try:
            isospring.read_patch_file(path)
            raise AssertionError("an unknown field was accepted")
        except isospring.InputError as e:
            assert "bad.json" in str(e) and "weight" in str(e)
    for bad in ([0.5], [0.5, float("nan")]):
        try:
            annulus().evaluate(bad)
            raise AssertionError(f"parameters {bad} were accepted for a surface")
        except isospring.InputError:
            pass


def test_timoshenko_tip_deflection():
    """examples/timoshenko_beam.json: degree 3 reproduces the cubic exact solution."""
    case = isospring.read_case(os.path.join(EXAMPLES, "timoshenko_beam.json"))
    assert case.dimension == 2 and case.formulation == "plane_stress"
    assert case.load_case_ids == ["end_shear"]
    result = isospring.analyze(case)
    f = isospring.field(case, result["end_shear"], 0, [1.0, 0.5])  # one point
    assert np.allclose(f["points"][0], [10, 1, 0], rtol=0, atol=1e-13)
    # Plane stress, end shear P (Timoshenko & Goodier): v(L, 0) = -P L^3 / (3 E I)
    # - P (4 + 5 nu) D^2 L / (24 E I), with I = D^3 / 12 per unit thickness.
    P, L, D, E, nu = 1.0, 10.0, 2.0, 1e5, 0.3
    inertia = D ** 3 / 12
    exact = -P * L ** 3 / (3 * E * inertia) - P * (4 + 5 * nu) * D ** 2 * L / (24 * E * inertia)
    assert abs(f["displacement"][0, 1] - exact) < 1e-9 * abs(exact), (f["displacement"], exact)
    # The clamp's reactions balance the downward end shear.
    assert abs(result["end_shear"].reaction_sum[1] - P) < 1e-9


def test_analysis_matches_the_program():
    """analyze() and `isospring analyze` are the same library call: the same numbers."""
    case_file = os.path.join(EXAMPLES, "cantilever_box.json")
    case = isospring.read_case(case_file)
    result = isospring.analyze(case)
    assert result.dofs == 3 * 22 * 6 * 6
    with tempfile.TemporaryDirectory() as folder:
        subprocess.run([PROGRAM, "analyze", case_file, "-o", folder, "-q"], check=True)
        with open(os.path.join(folder, "report.json")) as f:
            report = json.load(f)
        for lc, reported in zip(result.load_cases, report["load_cases"]):
            assert lc.id == reported["id"]
            for key in ("max_displacement", "strain_energy"):
                ours, theirs = getattr(lc, key), reported[key]
                assert abs(ours - theirs) <= 1e-12 * abs(theirs), (lc.id, key, ours, theirs)
            with open(os.path.join(folder, reported["control_displacements_file"])) as f:
                rows = list(csv.DictReader(f))
            table = np.array([[float(r[c]) for c in ("ux", "uy", "uz")] for r in rows])
            ours = lc.control_displacements[0]
            scale = np.max(np.abs(table))
            assert ours.shape == table.shape
            assert np.max(np.abs(ours - table)) <= 1e-12 * scale
    assert len(result.load_cases) == len(report["load_cases"]) == 3


def test_calibration_matches_the_program():
    """calibrate(case) applies the case's own "calibration" object, as the program does."""
    case_file = os.path.join(EXAMPLES, "calibrate_square.json")
    case = isospring.read_case(case_file)
    result = isospring.calibrate(case)
    with tempfile.TemporaryDirectory() as folder:
        subprocess.run([PROGRAM, "calibrate", case_file, "-o", folder, "-q"], check=True)
        with open(os.path.join(folder, "report.json")) as f:
            report = json.load(f)
    assert len(result["springs"]) == report["springs"]
    for ours, reported in ((result["fit"], report["fit"]), (result["holdout"], report["holdout"])):
        assert [e["id"] for e in ours] == [e["id"] for e in reported["load_cases"]]
        for e, r in zip(ours, reported["load_cases"]):
            for key, theirs in (("control", r["percent_e_rms"]), ("field", r["field_percent_e_rms"]),
                                ("surface", r["surface_percent_e_rms"])):
                value = e[key]["percent_e_rms"]
                assert abs(value - theirs) <= 1e-12 * abs(theirs), (e["id"], key, value, theirs)
    # Every spring joins two particles at its rest length.
    lengths = np.linalg.norm(result["positions"][result["springs"][:, 0]] -
                             result["positions"][result["springs"][:, 1]], axis=1)
    assert np.max(np.abs(lengths - result["rest_length"])) < 1e-12
    assert np.all(result["stiffness"] > 0)


def test_runtime_forces_and_jacobian():
    """isospring.RuntimeModel on the model.json the program writes: its forces are the springs'
    written out here in numpy, its Jacobian-vector product the central difference of them."""
    case_file = os.path.join(EXAMPLES, "calibrate_square.json")
    with tempfile.TemporaryDirectory() as folder:
        subprocess.run([PROGRAM, "calibrate", case_file, "-o", folder, "-q"], check=True)
        path = os.path.join(folder, "model.json")
        model = isospring.RuntimeModel(path)
        with open(path) as f:
            document = json.load(f)
    dim = document.get("dimension", 3)
    assert model.dimension == dim and model.particles == len(document["particles"])
    assert model.term_count(isospring.TERM_SPRINGS) == len(document["springs"])
    rest = np.array([p["x"][:dim] for p in document["particles"]])
    assert np.array_equal(model.rest_positions, rest)
    x = rest.ravel() + 0.01 * RNG.standard_normal(rest.size)
    v = RNG.standard_normal(rest.size)
    f, energy = model.forces(x, v)
    expected = np.zeros_like(x)
    expected_energy = 0.0
    for s in document["springs"]:
        i, j = s["i"], s["j"]
        l = x[dim * i:dim * i + dim] - x[dim * j:dim * j + dim]
        length = np.linalg.norm(l)
        rate = l @ (v[dim * i:dim * i + dim] - v[dim * j:dim * j + dim])
        force = -s["k"] * (length - s["L0"]) / length * l - s.get("c", 0.0) * rate / length**2 * l
        expected[dim * i:dim * i + dim] += force
        expected[dim * j:dim * j + dim] -= force
        expected_energy += 0.5 * s["k"] * (length - s["L0"]) ** 2
    assert np.max(np.abs(f - expected)) <= 1e-12 * np.max(np.abs(expected))
    assert abs(energy - expected_energy) <= 1e-12 * expected_energy
    dx = RNG.standard_normal(x.size)
    h = 1e-6
    central = (model.forces(x + h * dx, v)[0] - model.forces(x - h * dx, v)[0]) / (2 * h)
    df = model.force_jvp(x, dx, v)
    assert np.max(np.abs(df - central)) <= 1e-6 * np.max(np.abs(central))
    try:
        isospring.RuntimeModel(os.path.join(EXAMPLES, "calibrate_square.json"))
        raise AssertionError("a case file was loaded as a model")
    except isospring.InputError as e:
        assert "calibrate_square.json: format" in str(e), str(e)


def test_calibration_settings_are_the_case_files():
    """Keyword arguments are laid over the case's settings, under the case file's names, and are
    checked by the same reader (the program's messages, as exceptions)."""
    case = isospring.read_case(os.path.join(EXAMPLES, "calibrate_square.json"))
    # Grouped instead of per spring, fitted on one load case: fewer parameters, one fitted case.
    grouped = isospring.calibrate(case, grouping={"gamma": 0.5}, regularization=0.0,
                                  fit_load_cases=["u1_x"], holdout_load_cases=["v1_x"])
    assert [e["id"] for e in grouped["fit"]] == ["u1_x"]
    assert [e["id"] for e in grouped["holdout"]] == ["v1_x"]
    assert grouped["gamma"] == 0.5
    for settings, message in (
            ({"gamma": 1.5, "per_spring": False, "regularization": 0.0},
             "calibration.grouping.gamma must be in [0, 1), got 1.5"),
            ({"regularisation": 0.1},
             "calibration.regularisation: unknown field; did you mean 'regularization'")):
        try:
            isospring.calibrate(case, **settings)
            raise AssertionError(f"{settings} were accepted")
        except isospring.InputError as e:
            assert message in str(e), str(e)


def test_identify_matches_the_program():
    """identify() on the shipped plate with hidden gravity gives the program's report."""
    case_file = os.path.join(EXAMPLES, "identify", "plate_hidden_gravity.json")
    result = isospring.identify(isospring.read_case(case_file))
    with tempfile.TemporaryDirectory() as folder:
        subprocess.run([PROGRAM, "identify", case_file, "-o", folder, "-q"], check=True)
        with open(os.path.join(folder, "report.json")) as f:
            report = json.load(f)
    # What the case's description says was hidden in the data.
    assert result["effects_added"] == report["effects_added"] == ["gravity",
                                                                  "rigid_offset_per_load"]
    assert len(result["positions"]) == report["markers"]
    assert result["warnings"] == []  # a body-fitted plate: nothing adapted
    for key in ("rms_before", "rms_after", "max_before", "max_after", "noise_estimate"):
        assert abs(result[key] - report[key]) <= 1e-12 * abs(report[key]), key
    for ours, theirs in zip(result["parameters"], report["parameters"]):
        assert ours["name"] == theirs["name"]
        for key in ("value", "standard_error"):
            assert abs(ours[key] - theirs[key]) <= 1e-12 * abs(theirs[key]), (ours, theirs)
    # The summaries are those of the returned per-marker arrays (2D: x and y components).
    for stage in ("before", "after"):
        residual = (result["measured"] - result["model_" + stage])[:, :2]
        assert abs(np.sqrt(np.mean(residual ** 2)) / result["rms_" + stage] - 1) < 1e-12
        assert abs(np.max(np.abs(residual)) / result["max_" + stage] - 1) < 1e-12


def test_library_page_snippet_runs():
    """The Python example of docs/library.md ("Using isospring as a library"), as written."""
    with open(os.path.join(SOURCE, "docs", "library.md")) as f:
        page = f.read()
    section = page[page.index("## Python"):]
    start = section.index("```python\n") + len("```python\n")
    snippet = section[start:section.index("```", start)]
    assert "isospring.analyze" in snippet
    cwd = os.getcwd()
    os.chdir(SOURCE)  # the snippet's paths are relative to the repository, as on the page
    printed = io.StringIO()
    try:
        with contextlib.redirect_stdout(printed):
            exec(compile(snippet, "docs/library.md", "exec"), {})
    finally:
        os.chdir(cwd)
    lines = printed.getvalue().splitlines()
    # What the snippet's comments promise: the two arcs, the Timoshenko tip deflection.
    assert lines[0] == "[1. 2.]", lines
    assert abs(float(lines[1]) + 0.0051375) < 1e-10, lines
    assert lines[3] == "['gravity', 'rigid_offset_per_load']", lines


def test_immersed_analysis_matches_the_program():
    """analyze_immersed() and `isospring analyze` on an immersed case: the same numbers, and the
    clamp's reaction balances the weight from OpenCascade's volume."""
    case_file = os.path.join(EXAMPLES, "immersed", "cylinder_gravity.json")
    result = isospring.analyze_immersed(case_file)
    with tempfile.TemporaryDirectory() as folder:
        subprocess.run([PROGRAM, "analyze", case_file, "-o", folder, "-q"], check=True)
        with open(os.path.join(folder, "report.json")) as f:
            report = json.load(f)
    assert report["path"] == "immersed"
    assert result["cut_cells"] == report["immersion"]["cut_cells"]
    assert len(result["points"]) == report["surface"]["points"]
    assert len(result["triangles"]) == report["surface"]["triangles"]
    for ours, theirs in zip(result["load_cases"], report["load_cases"]):
        assert ours["id"] == theirs["id"]
        for key in ("strain_energy", "max_displacement", "max_von_mises"):
            assert abs(ours[key] - theirs[key]) <= 1e-12 * abs(theirs[key]), key
        # The case's own stabilisation sufficed: no solver warning, its ghost_fraction kept.
        assert ours["ghost_fraction"] == theirs["ghost_fraction"] == 0.02
        assert ours["warnings"] == []
        # The largest displacement is the one of the returned surface field.
        assert abs(np.max(np.linalg.norm(ours["displacement"], axis=1)) /
                   ours["max_displacement"] - 1) < 1e-12
    with open(case_file) as f:
        case = json.load(f)
    weight = result["opencascade"]["volume"] * case["material"]["density"] * 9.81
    reaction = result["load_cases"][0]["reaction_sum"]
    assert abs(reaction[0] - weight) <= 1e-5 * weight, (reaction, weight)
    try:
        isospring.analyze_immersed(os.path.join(EXAMPLES, "cantilever_box.json"))
        raise AssertionError("a body-fitted case was accepted")
    except isospring.InputError as e:
        assert "geometry" in str(e), str(e)


def test_immersed_bbar_matches_the_program():
    """analyze_immersed(volumetric="bbar") and `isospring analyze` of the case file with
    "analysis": {"volumetric": "bbar"}: the same B-bar numbers to 1e-12 on the shipped cylinder
    at nu = 0.49; a bad value is the case file's named error."""
    shipped = os.path.join(EXAMPLES, "immersed", "cylinder_gravity.json")
    with open(shipped) as f:
        case = json.load(f)
    case["geometry"]["file"] = os.path.join(EXAMPLES, "immersed", case["geometry"]["file"])
    case["material"]["nu"] = 0.49
    with tempfile.TemporaryDirectory() as folder:
        plain = os.path.join(folder, "cylinder.json")
        with open(plain, "w") as f:
            json.dump(case, f)
        case["analysis"] = {"volumetric": "bbar"}
        bbar_file = os.path.join(folder, "cylinder_bbar.json")
        with open(bbar_file, "w") as f:
            json.dump(case, f)
        subprocess.run([PROGRAM, "analyze", bbar_file, "-o", os.path.join(folder, "out"), "-q"],
                       check=True)
        with open(os.path.join(folder, "out", "report.json")) as f:
            report = json.load(f)
        by_argument = isospring.analyze_immersed(plain, volumetric="bbar")
        by_file = isospring.analyze_immersed(bbar_file)
        displacement = isospring.analyze_immersed(plain)
        assert report["volumetric"] == "bbar"
        assert by_argument["volumetric"] == by_file["volumetric"] == "bbar"
        assert displacement["volumetric"] == "displacement"
        for result in (by_argument, by_file):
            ours, theirs = result["load_cases"][0], report["load_cases"][0]
            for key in ("strain_energy", "max_displacement", "max_von_mises"):
                assert abs(ours[key] - theirs[key]) <= 1e-12 * abs(theirs[key]), key
        # Locking: the displacement formulation stores less energy under the same weight.
        assert (displacement["load_cases"][0]["strain_energy"] <
                by_file["load_cases"][0]["strain_energy"])
        try:
            isospring.analyze_immersed(plain, volumetric="bar")
            raise AssertionError("volumetric='bar' was accepted")
        except isospring.InputError as e:
            assert "volumetric" in str(e) and "'bar'" in str(e), str(e)


def test_calibrate_immersed_matches_the_program():
    """calibrate_immersed() and `isospring calibrate` on an immersed case: the same errors."""
    case_file = os.path.join(EXAMPLES, "immersed", "rounded_bracket_calibrate.json")
    result = isospring.calibrate_immersed(case_file)
    with tempfile.TemporaryDirectory() as folder:
        subprocess.run([PROGRAM, "calibrate", case_file, "-o", folder, "-q"], check=True)
        with open(os.path.join(folder, "report.json")) as f:
            report = json.load(f)
    assert report["path"] == "immersed"
    assert len(result["positions"]) == report["particles"]
    assert result["held_particles"] == report["held_particles"]
    held = report["holdout"]["load_cases"][0]
    assert result["holdout"][0]["id"] == held["id"]
    ours = result["holdout"][0]["control"]["percent_e_rms"]
    assert abs(ours - held["percent_e_rms"]) <= 1e-9 * held["percent_e_rms"], (ours, held)
    try:
        isospring.calibrate_immersed(case_file, matrix_approach=True)
        raise AssertionError("the matrix approach was accepted on an immersed case")
    except isospring.InputError as e:
        assert "no immersed form" in str(e), str(e)


def main():
    tests = [(name, f) for name, f in globals().items() if name.startswith("test_")]
    failed = 0
    for name, test in tests:
        try:
            test()
            print(f"ok      {name}")
        except Exception as e:  # report every failing test, not only the first
            failed += 1
            print(f"FAILED  {name}: {type(e).__name__}: {e}")
    print(f"{len(tests) - failed} of {len(tests)} passed")
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
