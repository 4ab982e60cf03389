#!/usr/bin/python3
# SPDX-License-Identifier: GPL-3.0-or-later
# Reads grainflow's output of non-spherical grains back with Python VTK and checks it.
"""Read-back test of the shape output (glyph arrays, polygon cells, CSV columns).

Usage (how CTest calls it; use /usr/bin/python3, where vtk and numpy are importable):

    /usr/bin/python3 tests/python/test_vtk_shapes.py GRAINFLOW_BINARY SOURCE_DIR [OUTPUT_DIR]

Without OUTPUT_DIR the test finds gf_unit_tests in the build folder of GRAINFLOW_BINARY (the
folder holding CMakeCache.txt, or the GF_UNIT_TESTS environment variable) and runs its
OutputSample.WritesShapeSampleForPythonReadback with GF_SAMPLE_OUTPUT_DIR set to a temporary
folder; with OUTPUT_DIR it reads the files already there. The sample is six grains of every
shape (SHAPE_SAMPLE below, in step with shape_store() in tests/unit/test_output.cpp), written at
two steps; between them every grain turns by 90 degrees about z. The expected values are
computed here from rotation matrices, independently of grainflow's quaternion code.

Checked: the particles .vtp (orientation quaternion w,x,y,z; axis; length; cap_radius;
cylinder_scale; cap_offset), that the ParaView capsule recipe of docs/output.md puts the
cylinder glyph where the grain's cylindrical part is, the polygons .vtp (one polygon cell per
polygon grain with its world vertices, counter-clockwise, and the cell data) and the CSV columns
(qw..qz, ax..az, integer shape and polygon).

Exit codes: 0 all checks passed, 1 a check failed, 2 bad usage, 77 skipped (vtk/numpy not
importable, or no gf_unit_tests to write the sample); the reason is printed.
"""

import csv
import math
import os
import shutil
import subprocess
import sys
import tempfile
import xml.etree.ElementTree as ET

SKIP = 77
SAMPLE_TEST = "OutputSample.WritesShapeSampleForPythonReadback"

SPHERE, SPHEROCYLINDER, DISK, POLYGON = 0, 1, 2, 3
DEG = math.pi / 180

# Body polygons of the table (index -> counter-clockwise vertices about the centroid, m; area).
POLYGONS = [
    ([(-0.005, -0.005), (0.005, -0.005), (0.005, 0.005), (-0.005, 0.005)], 1e-4),
    ([(0.006, 0.0), (-0.003, 0.0052), (-0.003, -0.0052)], 0.5 * 0.009 * 0.0104),
]

# id, material, shape, radius (bounding), half_length, rotations (applied left to right, each
# (axis, angle in rad)), polygon index, position, velocity, angular velocity.
SHAPE_SAMPLE = [
    (100, 0, SPHERE, 0.004, 0.0, [], -1, (0, 0, 0.01), (0, 0, -1), (0, 0, 0)),
    (101, 1, SPHEROCYLINDER, 0.008, 0.006, [((1, 0, 0), 90 * DEG)], -1,
     (0.02, 0, 0.01), (1, 0, 0), (0, 0, 2)),
    (102, 1, SPHEROCYLINDER, 0.005, 0.004, [((0, 1, 0), 30 * DEG), ((0, 0, 1), 40 * DEG)], -1,
     (0.04, 0.01, 0.02), (0, 0, 0), (0.5, 0, 0)),
    (103, 2, POLYGON, 0.005 * math.sqrt(2), 0.0, [((0, 0, 1), 30 * DEG)], 0,
     (0.1, 0.05, 0), (0.5, -0.5, 0), (0, 0, -3)),
    (104, 2, DISK, 0.006, 0.0, [((0, 0, 1), 90 * DEG)], -1, (0.2, 0, 0), (0, 0.25, 0), (0, 0, 1)),
    (105, 3, POLYGON, 0.006, 0.0, [((0, 0, 1), -45 * DEG)], 1,
     (0.15, 0.02, 0), (-0.1, 0, 0), (0, 0, 0.5)),
]
STEP_TURN = ((0, 0, 1), 90 * DEG)  # applied to every grain between step 0 and step 1
N_STEPS = 2


class Checks:
    """Counts passed and failed checks; prints each failure."""

    def __init__(self):
        self.passed = 0
        self.failed = 0

    def check(self, ok, what):
        if ok:
            self.passed += 1
        else:
            self.failed += 1
            print(f"FAIL: {what}")
        return ok


def skip(reason):
    print(f"SKIP: {reason}")
    sys.exit(SKIP)


# ---- expected values ---------------------------------------------------------------------------

def rotation_matrix(np, axis, angle):
    """Rodrigues' rotation matrix about the unit vector `axis` by `angle` (rad)."""
    k = np.asarray(axis, dtype=float)
    k = k / np.linalg.norm(k)
    kx = np.array([[0, -k[2], k[1]], [k[2], 0, -k[0]], [-k[1], k[0], 0]])
    return np.eye(3) + math.sin(angle) * kx + (1 - math.cos(angle)) * kx @ kx


def quat_mul(a, b):
    aw, ax, ay, az = a
    bw, bx, by, bz = b
    return (aw * bw - ax * bx - ay * by - az * bz, aw * bx + ax * bw + ay * bz - az * by,
            aw * by - ax * bz + ay * bw + az * bx, aw * bz + ax * by - ay * bx + az * bw)


def quat_axis_angle(axis, angle):
    n = math.sqrt(sum(c * c for c in axis))
    s = math.sin(angle / 2)
    return (math.cos(angle / 2), s * axis[0] / n, s * axis[1] / n, s * axis[2] / n)


def expected_state(np, step):
    """Per grain: (quaternion w,x,y,z; rotation matrix body -> world) at output `step`."""
    out = []
    for g in SHAPE_SAMPLE:
        rotations = list(g[5]) + [STEP_TURN] * step
        q = (1.0, 0.0, 0.0, 0.0)
        r = np.eye(3)
        for axis, angle in rotations:  # each later rotation acts on the left
            q = quat_mul(quat_axis_angle(axis, angle), q)
            r = rotation_matrix(np, axis, angle) @ r
        out.append((np.array(q), r))
    return out


def expected_axis(np, shape, r):
    body = np.array([1.0, 0, 0]) if shape in (DISK, POLYGON) else np.array([0, 0, 1.0])
    return r @ body


def expected_cap_radius(g):
    return 0.0 if g[2] == POLYGON else g[3] - g[4]


# ---- reading -----------------------------------------------------------------------------------

def read_vtp(path, vtk):
    errors = []
    reader = vtk.vtkXMLPolyDataReader()
    reader.AddObserver("ErrorEvent", lambda obj, ev: errors.append(f"{ev} from {obj.GetClassName()}"))
    reader.SetFileName(path)
    reader.Update()
    return reader.GetOutput(), errors


def arrays_of(attrs, np, vtk_to_numpy):
    out = {}
    for i in range(attrs.GetNumberOfArrays()):
        a = attrs.GetArray(i)
        if a is not None:
            out[a.GetName()] = np.asarray(vtk_to_numpy(a))
    return out


def series_files(c, pvd):
    """The data set files of a .pvd, in order; [] (failure printed) when unreadable."""
    if not c.check(os.path.isfile(pvd), f"{pvd} missing"):
        return []
    try:
        root = ET.parse(pvd).getroot()
    except ET.ParseError as e:
        c.check(False, f"{pvd}: not well-formed XML: {e}")
        return []
    sets = root.findall("./Collection/DataSet")
    return [os.path.join(os.path.dirname(pvd), s.get("file", "")) for s in sets]


# ---- checks ------------------------------------------------------------------------------------

def close(np, a, b, tol=1e-14):
    return a.shape == np.asarray(b).shape and bool(np.allclose(a, b, rtol=0, atol=tol))


def check_particles(c, label, ds, np, vtk_to_numpy, step):
    n = len(SHAPE_SAMPLE)
    c.check(ds.GetNumberOfPoints() == n, f"{label}: {ds.GetNumberOfPoints()} points, expected {n}")
    c.check(ds.GetNumberOfVerts() == n, f"{label}: {ds.GetNumberOfVerts()} vertex cells")
    pd = arrays_of(ds.GetPointData(), np, vtk_to_numpy)
    want = {"orientation": (n, 4), "axis": (n, 3), "length": (n,), "cap_radius": (n,),
            "cylinder_scale": (n, 3), "cap_offset": (n, 3), "shape": (n,), "half_length": (n,),
            "polygon": (n,), "id": (n,), "radius": (n,)}
    for key, shape in want.items():
        if not c.check(key in pd, f"{label}: no point array '{key}' (has {sorted(pd)})"):
            return
        c.check(pd[key].shape == shape, f"{label}: '{key}' has shape {pd[key].shape}, expected {shape}")
    for key in ("shape", "polygon", "id"):
        c.check(np.issubdtype(pd[key].dtype, np.integer), f"{label}: '{key}' is {pd[key].dtype}")
    c.check(pd["id"].tolist() == [g[0] for g in SHAPE_SAMPLE], f"{label}: ids {pd['id']}")
    c.check(pd["shape"].tolist() == [g[2] for g in SHAPE_SAMPLE], f"{label}: shapes {pd['shape']}")
    c.check(pd["polygon"].tolist() == [g[6] for g in SHAPE_SAMPLE], f"{label}: polygon {pd['polygon']}")
    pts = vtk_to_numpy(ds.GetPoints().GetData())
    c.check(close(np, pts, np.array([g[7] for g in SHAPE_SAMPLE], dtype=float)), f"{label}: positions")

    state = expected_state(np, step)
    for i, g in enumerate(SHAPE_SAMPLE):
        q, r = state[i]
        who = f"{label}: grain id {g[0]}"
        c.check(close(np, pd["orientation"][i], q), f"{who}: quaternion {pd['orientation'][i]}, expected {q} (w, x, y, z)")
        a = expected_axis(np, g[2], r)
        c.check(close(np, pd["axis"][i], a), f"{who}: axis {pd['axis'][i]}, expected {a}")
        c.check(abs(np.linalg.norm(pd["axis"][i]) - 1) < 1e-14, f"{who}: axis not unit")
        h, rc = g[4], expected_cap_radius(g)
        c.check(abs(pd["half_length"][i] - h) < 1e-18, f"{who}: half_length {pd['half_length'][i]}")
        c.check(abs(pd["length"][i] - 2 * g[3]) < 1e-17, f"{who}: length {pd['length'][i]}, expected {2 * g[3]}")
        if g[2] == SPHEROCYLINDER:
            c.check(abs(pd["length"][i] - 2 * (h + rc)) < 1e-17, f"{who}: length is not tip to tip")
        c.check(abs(pd["cap_radius"][i] - rc) < 1e-17, f"{who}: cap_radius {pd['cap_radius'][i]}, expected {rc}")
        c.check(close(np, pd["cylinder_scale"][i], [2 * h, 2 * rc, 2 * rc], 1e-17),
                f"{who}: cylinder_scale {pd['cylinder_scale'][i]}")
        c.check(close(np, pd["cap_offset"][i], h * a, 1e-16), f"{who}: cap_offset {pd['cap_offset'][i]}")
    return pd, pts


def paraview_glyph_points(np, vtk, source_pts, source_transform, x, orient, scale):
    """Where ParaView's Glyph filter (vtkPVGlyphFilter::Execute) puts a glyph's points: the
    source transform (Glyph Transform) first, then the per-point scale in glyph axes, then the
    rotation taking glyph x onto the orientation vector, then the translation to the point."""
    t = vtk.vtkTransform()
    t.Translate(*x)
    v = np.asarray(orient, dtype=float)
    m = np.linalg.norm(v)
    if m > 0:
        if v[1] == 0 and v[2] == 0:
            if v[0] < 0:
                t.RotateWXYZ(180.0, 0, 1, 0)
        else:
            t.RotateWXYZ(180.0, (v[0] + m) / 2, v[1] / 2, v[2] / 2)
    t.Scale(*[s if s != 0 else 1e-10 for s in scale])
    out = []
    for p in source_pts:
        out.append(t.TransformPoint(source_transform.TransformPoint(p)))
    return np.array(out)


def check_capsule_recipe(c, label, pd, pts, np, vtk, vtk_to_numpy):
    """The docs/output.md recipe: Cylinder glyph (VTK: along y, radius 0.5, height 1), Glyph
    Transform Rotate (0, 0, 90), orientation `axis`, scale `cylinder_scale` by components. The
    glyph must be the grain's cylindrical part: |axial| <= half_length, radial <= r_cap, with the
    rim at exactly r_cap and the end faces at exactly +-half_length."""
    cyl = vtk.vtkCylinderSource()
    cyl.SetResolution(24)
    cyl.Update()
    src = vtk_to_numpy(cyl.GetOutput().GetPoints().GetData()).astype(float)
    rot = vtk.vtkTransform()
    rot.RotateZ(90)
    for i, g in enumerate(SHAPE_SAMPLE):
        if g[2] != SPHEROCYLINDER:
            continue
        glyph = paraview_glyph_points(np, vtk, src, rot, pts[i], pd["axis"][i], pd["cylinder_scale"][i])
        a = pd["axis"][i]
        d = glyph - pts[i]
        axial = d @ a
        radial = np.linalg.norm(d - np.outer(axial, a), axis=1)
        h, rc = g[4], expected_cap_radius(g)
        who = f"{label}: capsule glyph of grain id {g[0]}"
        c.check(abs(axial.max() - h) < 1e-12 and abs(axial.min() + h) < 1e-12,
                f"{who}: spans [{axial.min()}, {axial.max()}] along the axis, expected +-{h}")
        c.check(abs(radial.max() - rc) < 1e-12, f"{who}: radius {radial.max()}, expected {rc}")
        # The caps: spheres of radius cap_radius at x +- cap_offset end the cylinder.
        c.check(close(np, pts[i] + pd["cap_offset"][i], pts[i] + h * a, 1e-15), f"{who}: cap centre")


def check_polygons(c, label, ds, np, vtk_to_numpy, step):
    grains = [g for g in SHAPE_SAMPLE if g[2] == POLYGON]
    state = {g[0]: s for g, s in zip(SHAPE_SAMPLE, expected_state(np, step))}
    c.check(ds.GetNumberOfPolys() == len(grains), f"{label}: {ds.GetNumberOfPolys()} polygons, expected {len(grains)}")
    c.check(ds.GetNumberOfVerts() == 0, f"{label}: vertex cells in the polygon file")
    cd = arrays_of(ds.GetCellData(), np, vtk_to_numpy)
    m = len(grains)
    for key, shape in (("id", (m,)), ("material", (m,)), ("velocity", (m, 3)),
                       ("angular_velocity", (m, 3)), ("speed", (m,)), ("area", (m,))):
        if not c.check(key in cd, f"{label}: no cell array '{key}' (has {sorted(cd)})"):
            return
        c.check(cd[key].shape == shape, f"{label}: '{key}' has shape {cd[key].shape}, expected {shape}")
    c.check(cd["id"].tolist() == [g[0] for g in grains], f"{label}: ids {cd['id']}")
    c.check(cd["material"].tolist() == [g[1] for g in grains], f"{label}: materials {cd['material']}")
    c.check(close(np, cd["velocity"], np.array([g[8] for g in grains], dtype=float)), f"{label}: velocity")
    c.check(close(np, cd["angular_velocity"], np.array([g[9] for g in grains], dtype=float)),
            f"{label}: angular_velocity")
    c.check(close(np, cd["speed"], np.linalg.norm(np.array([g[8] for g in grains], dtype=float), axis=1)),
            f"{label}: speed")
    pts = vtk_to_numpy(ds.GetPoints().GetData())
    for k, g in enumerate(grains):
        cell = ds.GetCell(k)
        who = f"{label}: polygon of grain id {g[0]}"
        # vtkPolyData reports a Polys cell of 3 or 4 points as a triangle (5) or quad (9).
        c.check(cell.GetCellType() in (5, 7, 9), f"{who}: cell type {cell.GetCellType()}, not a polygon")
        ids = [cell.GetPointId(j) for j in range(cell.GetNumberOfPoints())]
        body, area = POLYGONS[g[6]]
        if not c.check(len(ids) == len(body), f"{who}: {len(ids)} vertices, expected {len(body)}"):
            continue
        r = state[g[0]][1]
        want = np.array([np.asarray(g[7], dtype=float) + r @ np.array([vx, vy, 0.0]) for vx, vy in body])
        got = pts[ids]
        c.check(close(np, got, want), f"{who}: vertices\n{got}\nexpected\n{want}")
        # Counter-clockwise seen from +z, with the table's area (shoelace).
        xs, ys = got[:, 0], got[:, 1]
        signed = 0.5 * float(np.sum(xs * np.roll(ys, -1) - np.roll(xs, -1) * ys))
        c.check(abs(signed - area) < 1e-15, f"{who}: signed area {signed}, expected {area}")
        c.check(abs(cd["area"][k] - area) < 1e-18, f"{who}: area {cd['area'][k]}")


def check_csv(c, path, np, step):
    if not c.check(os.path.isfile(path), f"{path} missing"):
        return
    with open(path, newline="", encoding="utf-8") as f:
        rows = list(csv.reader(f))
    header, body = rows[0], rows[1:]
    names = ("shape", "half_length", "qw", "qx", "qy", "qz", "ax", "ay", "az", "polygon")
    missing = [name for name in names if name not in header]
    if not c.check(not missing, f"{path}: no columns {missing} in {header}"):
        return
    col = {h: k for k, h in enumerate(header)}
    c.check(header.index("ax") == header.index("qz") + 1, f"{path}: ax does not follow qz")
    c.check(len(body) == len(SHAPE_SAMPLE), f"{path}: {len(body)} rows")
    state = expected_state(np, step)
    for row, g, (q, r) in zip(body, SHAPE_SAMPLE, state):
        who = f"{path}: grain id {g[0]}"
        c.check(row[col["id"]] == str(g[0]), f"{who}: id '{row[col['id']]}'")
        c.check(row[col["shape"]] == str(g[2]), f"{who}: shape '{row[col['shape']]}' (integers as integers)")
        c.check(row[col["polygon"]] == str(g[6]), f"{who}: polygon '{row[col['polygon']]}'")
        c.check(float(row[col["half_length"]]) == g[4], f"{who}: half_length")
        got_q = np.array([float(row[col[k]]) for k in ("qw", "qx", "qy", "qz")])
        c.check(close(np, got_q, q), f"{who}: q {got_q}, expected {q}")
        got_a = np.array([float(row[col[k]]) for k in ("ax", "ay", "az")])
        c.check(close(np, got_a, expected_axis(np, g[2], r)), f"{who}: axis {got_a}")


def check_output(c, folder):
    try:
        import numpy as np
        import vtk
        from vtk.util.numpy_support import vtk_to_numpy
    except ImportError as e:
        skip(f"vtk / numpy not importable by {sys.executable}: {e}")

    particle_files = series_files(c, os.path.join(folder, "particles.pvd"))
    polygon_files = series_files(c, os.path.join(folder, "polygons.pvd"))
    c.check(len(particle_files) == N_STEPS, f"particles.pvd lists {len(particle_files)} files")
    c.check(len(polygon_files) == N_STEPS, f"polygons.pvd lists {len(polygon_files)} files")
    for step, path in enumerate(particle_files):
        label = os.path.basename(path)
        ds, errors = read_vtp(path, vtk)
        if not c.check(not errors and ds is not None, f"{label}: VTK reader errors {errors}"):
            continue
        got = check_particles(c, label, ds, np, vtk_to_numpy, step)
        if got:
            check_capsule_recipe(c, label, got[0], got[1], np, vtk, vtk_to_numpy)
    for step, path in enumerate(polygon_files):
        label = os.path.basename(path)
        ds, errors = read_vtp(path, vtk)
        if c.check(not errors and ds is not None, f"{label}: VTK reader errors {errors}"):
            check_polygons(c, label, ds, np, vtk_to_numpy, step)
    for step in range(N_STEPS):
        check_csv(c, os.path.join(folder, f"particles_{step:06d}.csv"), np, step)


def find_unit_tests(binary):
    """gf_unit_tests of the build that made `binary`, or None."""
    env = os.environ.get("GF_UNIT_TESTS")
    if env:
        return env if os.access(env, os.X_OK) else None
    d = os.path.dirname(os.path.abspath(binary))
    while True:
        if os.path.isfile(os.path.join(d, "CMakeCache.txt")):
            exe = os.path.join(d, "tests", "gf_unit_tests")
            return exe if os.access(exe, os.X_OK) else None
        parent = os.path.dirname(d)
        if parent == d:
            return None
        d = parent


def write_sample(c, unit_tests, out):
    env = dict(os.environ, GF_SAMPLE_OUTPUT_DIR=out)
    cmd = [unit_tests, f"--gtest_filter={SAMPLE_TEST}", "--gtest_also_run_disabled_tests"]
    try:
        p = subprocess.run(cmd, capture_output=True, text=True, timeout=120, env=env)
    except (OSError, subprocess.TimeoutExpired) as e:
        return c.check(False, f"{' '.join(cmd)} failed: {e}")
    ok = p.returncode == 0 and "[  PASSED  ] 1 test" in p.stdout
    if not c.check(ok, f"{' '.join(cmd)} exited with {p.returncode} or did not run {SAMPLE_TEST}"):
        print("--- stdout ---\n" + p.stdout[-4000:] + "\n--- stderr ---\n" + p.stderr[-4000:])
    return ok


def main(argv):
    if len(argv) not in (3, 4):
        print(__doc__)
        return 2
    binary = os.path.abspath(argv[1])
    c = Checks()
    work = None
    if len(argv) == 4:
        check_output(c, argv[3])
    else:
        unit_tests = find_unit_tests(binary)
        if unit_tests is None:
            skip(f"no gf_unit_tests next to {binary} (set GF_UNIT_TESTS) to write the sample")
        try:
            import numpy  # noqa: F401
            import vtk  # noqa: F401
        except ImportError as e:
            skip(f"vtk / numpy not importable by {sys.executable}: {e}")
        work = tempfile.mkdtemp(prefix="gf_vtk_shapes_")
        if write_sample(c, unit_tests, work):
            check_output(c, work)
    print(f"{c.passed} passed, {c.failed} failed")
    if work:
        if c.failed == 0:
            shutil.rmtree(work, ignore_errors=True)
        else:
            print(f"(kept {work} for inspection)")
    return 0 if c.failed == 0 else 1


if __name__ == "__main__":
    sys.exit(main(sys.argv))
