#!/usr/bin/python3
# SPDX-License-Identifier: GPL-3.0-or-later
# Reads grainflow's ParaView output (.pvd + .vtp) back with Python VTK and checks its content.
"""Read-back test of grainflow's VTK output with Debian's python3-vtk9 and numpy.

Usage (how CTest calls it; use /usr/bin/python3, where vtk and numpy are importable):

    /usr/bin/python3 tests/python/test_vtk_readback.py GRAINFLOW_BINARY SOURCE_DIR [OUTPUT_DIR]

Without OUTPUT_DIR the test writes a tiny case (four spheres falling on a floor) into a
temporary folder, runs `grainflow run CASE --output DIR --overwrite`, and reads every .pvd
found in DIR. With OUTPUT_DIR it only reads the files already there (for example those written
by the unit test OutputSample.WritesSeriesForPythonReadback with GF_SAMPLE_OUTPUT_DIR set).

Exit codes: 0 all checks passed, 1 a check failed, 2 bad usage, 77 skipped (the binary cannot
run a case yet, or vtk/numpy are not importable); the reason is printed.
"""

import math
import os
import re
import shutil
import subprocess
import sys
import tempfile
import xml.etree.ElementTree as ET

SKIP = 77

CASE_YAML = """\
name: vtk_readback
dimension: 3
time: {step: 1.0e-5, end: 0.02}
domain: {min: [-0.05, -0.05, -0.01], max: [0.05, 0.05, 0.1], periodic: [false, false, false]}
gravity: [0, 0, -9.81]
materials:
  glass: {density: 2500, youngs_modulus: 1.0e7, poisson_ratio: 0.3}
contacts:
  - between: [glass, glass]
    model: hertz_mindlin
    restitution: 0.5
    friction: 0.5
particles:
  - shape: sphere
    radius: 0.005
    material: glass
    positions: [[0, 0, 0.006], [0.012, 0, 0.006], [0, 0.012, 0.02], [0.012, 0.012, 0.03]]
    velocities: [[0, 0, 0], [0, 0, 0], [0, 0, -0.1], [0.05, 0, 0]]
walls:
  - {name: floor, plane: {point: [0, 0, 0], normal: [0, 0, 1]}, material: glass}
output:
  directory: out
  vtk: {every: 0.005}
"""
N_PARTICLES = 4
RADIUS = 0.005


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


def binary_can_run(binary):
    """None when `binary` has a `run` command, else why not."""
    if not os.path.isfile(binary) or not os.access(binary, os.X_OK):
        return f"no executable at {binary}"
    try:
        p = subprocess.run([binary, "--help"], capture_output=True, text=True, timeout=30)
    except (OSError, subprocess.TimeoutExpired) as e:
        return f"'{binary} --help' failed: {e}"
    text = p.stdout + p.stderr
    if not re.search(r"\brun\b", text):
        return f"'{binary} --help' lists no 'run' command yet (the simulation is not wired)"
    return None


def run_case(binary, work):
    """Writes the case, runs it; returns the output folder or None (failure printed)."""
    case = os.path.join(work, "case.yaml")
    with open(case, "w", encoding="utf-8") as f:
        f.write(CASE_YAML)
    out = os.path.join(work, "out")
    cmd = [binary, "run", case, "--output", out, "--overwrite"]
    try:
        p = subprocess.run(cmd, capture_output=True, text=True, timeout=300, cwd=work)
    except subprocess.TimeoutExpired:
        print(f"FAIL: {' '.join(cmd)} timed out")
        return None
    if p.returncode != 0:
        print(f"FAIL: {' '.join(cmd)} exited with {p.returncode}")
        print("--- stdout ---\n" + p.stdout[-4000:] + "\n--- stderr ---\n" + p.stderr[-4000:])
        return None
    return out


def find_pvds(folder):
    found = []
    for root, _dirs, files in os.walk(folder):
        found += [os.path.join(root, f) for f in files if f.endswith(".pvd")]
    return sorted(found)


def read_vtk(path, vtk):
    """Reads one XML VTK file; returns (data set, list of reader errors)."""
    errors = []
    reader = vtk.vtkXMLPolyDataReader() if path.endswith(".vtp") else vtk.vtkXMLGenericDataObjectReader()
    reader.AddObserver("ErrorEvent", lambda obj, ev: errors.append(f"{ev} from {obj.GetClassName()}"))
    reader.SetFileName(path)
    reader.Update()
    return reader.GetOutput(), errors


def arrays_of(attrs, np, vtk_to_numpy):
    """name -> numpy array for every array of a vtkPointData / vtkCellData."""
    out = {}
    for i in range(attrs.GetNumberOfArrays()):
        a = attrs.GetArray(i)
        if a is not None:
            out[a.GetName()] = np.asarray(vtk_to_numpy(a))
    return out


def check_particles(c, name, ds, np, vtk_to_numpy, expected_n, floor_z):
    n = ds.GetNumberOfPoints()
    if expected_n is not None:
        c.check(n == expected_n, f"{name}: {n} points, expected {expected_n}")
    c.check(ds.GetNumberOfVerts() == n, f"{name}: {ds.GetNumberOfVerts()} vertex cells for {n} points")
    pd = arrays_of(ds.GetPointData(), np, vtk_to_numpy)
    pts = vtk_to_numpy(ds.GetPoints().GetData()) if n > 0 else np.zeros((0, 3))
    c.check(pts.shape == (n, 3), f"{name}: points shape {pts.shape}")
    c.check(bool(np.all(np.isfinite(pts))), f"{name}: non-finite positions")
    for key, shape in (("radius", (n,)), ("velocity", (n, 3)), ("id", (n,))):
        if not c.check(key in pd, f"{name}: no point array '{key}' (has {sorted(pd)})"):
            continue
        c.check(pd[key].shape == shape, f"{name}: '{key}' has shape {pd[key].shape}, expected {shape}")
    if "id" in pd:
        ids = pd["id"]
        c.check(np.issubdtype(ids.dtype, np.integer), f"{name}: ids are {ids.dtype}, not integers")
        c.check(len(np.unique(ids)) == len(ids), f"{name}: ids are not unique")
    for key, a in pd.items():
        if np.issubdtype(a.dtype, np.floating):
            c.check(bool(np.all(np.isfinite(a))), f"{name}: non-finite values in '{key}'")
    if "radius" in pd:
        c.check(bool(np.all(pd["radius"] > 0)), f"{name}: non-positive radius")
        if floor_z is not None and n > 0:
            sunk = pts[:, 2] < floor_z - pd["radius"]
            c.check(not bool(np.any(sunk)), f"{name}: particles below the floor: z = {pts[sunk, 2]}")
    if "speed" in pd and "velocity" in pd and pd["velocity"].shape == (n, 3):
        c.check(bool(np.allclose(pd["speed"], np.linalg.norm(pd["velocity"], axis=1), rtol=1e-12, atol=0)),
                f"{name}: 'speed' is not |velocity|")
    # Shapes (docs/output.md): unit quaternions (w, x, y, z) and unit axes.
    for key, comps in (("orientation", 4), ("axis", 3)):
        if key in pd and c.check(pd[key].shape == (n, comps), f"{name}: '{key}' has shape {pd[key].shape}"):
            norms = np.linalg.norm(pd[key], axis=1) if n > 0 else np.zeros(0)
            c.check(bool(np.allclose(norms, 1.0, rtol=0, atol=1e-9)), f"{name}: '{key}' not unit: {norms}")
    return set(pd["id"].tolist()) if "id" in pd else None


def check_polygons(c, name, ds, np, vtk_to_numpy):
    """A polygons_*.vtp: one polygon cell (>= 3 points, finite) per polygon grain, unique ids."""
    m = ds.GetNumberOfCells()
    c.check(ds.GetNumberOfPolys() == m, f"{name}: {m} cells but {ds.GetNumberOfPolys()} polygons")
    cd = arrays_of(ds.GetCellData(), np, vtk_to_numpy)
    for key, shape in (("id", (m,)), ("velocity", (m, 3)), ("angular_velocity", (m, 3))):
        if c.check(key in cd, f"{name}: no cell array '{key}' (has {sorted(cd)})") and m > 0:
            c.check(cd[key].shape == shape, f"{name}: '{key}' has shape {cd[key].shape}, expected {shape}")
    if "id" in cd:
        c.check(len(np.unique(cd["id"])) == len(cd["id"]), f"{name}: polygon ids are not unique")
    if ds.GetNumberOfPoints() > 0:
        c.check(bool(np.all(np.isfinite(vtk_to_numpy(ds.GetPoints().GetData())))), f"{name}: non-finite vertices")
    for k in range(m):
        c.check(ds.GetCell(k).GetNumberOfPoints() >= 3, f"{name}: polygon {k} has fewer than 3 vertices")


def check_walls(c, name, ds, np, vtk_to_numpy):
    m = ds.GetNumberOfCells()
    cd = arrays_of(ds.GetCellData(), np, vtk_to_numpy)
    for key, shape in (("wall_id", (m,)), ("wall_force", (m, 3))):
        if not c.check(key in cd, f"{name}: no cell array '{key}' (has {sorted(cd)})"):
            continue
        a = cd[key].reshape(shape) if m == 0 else cd[key]
        c.check(a.shape == shape, f"{name}: '{key}' has shape {a.shape}, expected {shape}")
        c.check(bool(np.all(np.isfinite(a))), f"{name}: non-finite values in '{key}'")


def check_output(c, folder, expected_n, floor_z):
    try:
        import numpy as np
        import vtk
        from vtk.util.numpy_support import vtk_to_numpy
    except ImportError as e:
        skip(f"vtk / numpy not importable by {sys.executable}: {e}")

    pvds = find_pvds(folder)
    if not c.check(len(pvds) > 0, f"no .pvd file under {folder}"):
        return
    n_particle_sets = 0
    for pvd in pvds:
        rel = os.path.relpath(pvd, folder)
        try:
            root = ET.parse(pvd).getroot()
        except ET.ParseError as e:
            c.check(False, f"{rel}: not well-formed XML: {e}")
            continue
        c.check(root.tag == "VTKFile" and root.get("type") == "Collection", f"{rel}: not a VTK collection")
        sets = root.findall("./Collection/DataSet")
        if not c.check(len(sets) > 0, f"{rel}: no DataSet entries"):
            continue
        times = [float(s.get("timestep", "nan")) for s in sets]
        c.check(all(math.isfinite(t) for t in times), f"{rel}: non-finite timestep in {times}")
        c.check(all(a <= b for a, b in zip(times, times[1:])), f"{rel}: timesteps not increasing: {times}")
        id_sets = []
        for s in sets:
            f = s.get("file")
            path = os.path.join(os.path.dirname(pvd), f or "")
            label = f"{rel} -> {f}"
            if not c.check(f and os.path.isfile(path), f"{label}: file missing"):
                continue
            ds, errors = read_vtk(path, vtk)
            if not c.check(not errors and ds is not None, f"{label}: VTK reader errors {errors}"):
                continue
            point_names = {ds.GetPointData().GetArrayName(i) for i in range(ds.GetPointData().GetNumberOfArrays())}
            cell_names = {ds.GetCellData().GetArrayName(i) for i in range(ds.GetCellData().GetNumberOfArrays())}
            if "radius" in point_names:
                n_particle_sets += 1
                ids = check_particles(c, label, ds, np, vtk_to_numpy, expected_n, floor_z)
                if ids is not None:
                    id_sets.append(ids)
            elif "wall_id" in cell_names:
                check_walls(c, label, ds, np, vtk_to_numpy)
            elif "id" in cell_names:
                check_polygons(c, label, ds, np, vtk_to_numpy)
            else:
                c.check(ds.GetNumberOfPoints() >= 0, f"{label}: unreadable")
        if id_sets:
            c.check(all(ids == id_sets[0] for ids in id_sets), f"{rel}: particle ids change over time")
    c.check(n_particle_sets > 0, f"no particle data set (with a 'radius' array) under {folder}")


def main(argv):
    if len(argv) not in (3, 4):
        print(__doc__)
        return 2
    binary, _source_dir = os.path.abspath(argv[1]), argv[2]
    c = Checks()
    work = None
    if len(argv) == 4:
        check_output(c, argv[3], None, None)
    else:
        why = binary_can_run(binary)
        if why:
            skip(why)
        work = tempfile.mkdtemp(prefix="gf_vtk_readback_")
        out = run_case(binary, work)
        if c.check(out is not None, "the case ran"):
            check_output(c, out, N_PARTICLES, 0.0)
    print(f"{c.passed} passed, {c.failed} failed")
    if work:
        if c.failed == 0:
            shutil.rmtree(work, ignore_errors=True)
        else:
            print(f"(kept {work} for inspection)")
    return 0 if c.failed == 0 else 1


if __name__ == "__main__":
    sys.exit(main(sys.argv))
