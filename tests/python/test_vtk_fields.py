#!/usr/bin/python3
# SPDX-License-Identifier: GPL-3.0-or-later
# Reads grainflow's fluid fields (.vtu of fluid_fem, .vti of CFD-DEM) back with Python VTK.
"""Read-back test of the fluid fields' ParaView output with Debian's python3-vtk9 and numpy.

Usage (how CTest calls it):

    /usr/bin/python3 tests/python/test_vtk_fields.py GRAINFLOW_BINARY SOURCE_DIR

Runs two shipped cases into a temporary folder and reads every file their .pvd lists:
- cases/fluid_fem/schaefer_turek_2d1 (steady, 0.5 s): quadratic triangles (VTK type 22), the
  parabolic inflow u = 4 U y (H - y) / H^2 at the inflow nodes (x = 0) to 1e-12, no-slip
  (u = 0) on the walls y = 0 and y = H, finite pressure;
- cases/cfd_dem/fluidized_bed for 3 ms with fields every 1 ms: ImageData with one point more
  than cells along each axis, fluid fraction in [min_fraction, 1] and below 1 somewhere (the bed),
  velocity and pressure finite, four time steps in fluid.pvd.

Exit codes: 0 passed, 1 a check failed, 2 bad usage, 77 skipped (vtk/numpy not importable).
"""

import os
import shutil
import subprocess
import sys
import tempfile
import xml.etree.ElementTree as ET

SKIP = 77


def main(argv):
    if len(argv) != 3:
        print(__doc__)
        return 2
    try:
        import numpy as np
        import vtk
        from vtk.util.numpy_support import vtk_to_numpy
    except ImportError as e:
        print(f"SKIP: {e}")
        return SKIP
    binary, source = os.path.abspath(argv[1]), os.path.abspath(argv[2])
    failed = []

    def check(ok, what):
        if not ok:
            failed.append(what)
            print(f"FAIL: {what}")

    def run(case, out, *extra):
        cmd = [binary, "run", os.path.join(source, case), "--output", out, "--overwrite", "-q", *extra]
        p = subprocess.run(cmd, capture_output=True, text=True, timeout=300)
        check(p.returncode == 0, f"{' '.join(cmd)} exited with {p.returncode}: {p.stderr[-2000:]}")
        return p.returncode == 0

    def read(path, reader):
        errors = []
        reader.AddObserver("ErrorEvent", lambda obj, ev: errors.append(ev))
        reader.SetFileName(path)
        reader.Update()
        check(not errors, f"{path}: reader errors {errors}")
        return reader.GetOutput()

    def listed(pvd):
        folder = os.path.dirname(pvd)
        return [os.path.join(folder, d.get("file")) for d in ET.parse(pvd).getroot().iter("DataSet")]

    work = tempfile.mkdtemp(prefix="gf_vtk_fields_")
    fem = os.path.join(work, "fem")
    if run("cases/fluid_fem/schaefer_turek_2d1/case.yaml", fem):
        files = listed(os.path.join(fem, "fem_fields.pvd")) + [os.path.join(fem, "fem_mesh.vtu")]
        for f in files:
            g = read(f, vtk.vtkXMLUnstructuredGridReader())
            n = g.GetNumberOfCells()
            check(n > 1000, f"{f}: {n} cells")
            types = {g.GetCellType(i) for i in range(n)}
            check(types == {22}, f"{f}: cell types {types}, expected quadratic triangles (22)")
            x = vtk_to_numpy(g.GetPoints().GetData())
            u = vtk_to_numpy(g.GetPointData().GetArray("velocity"))
            p = vtk_to_numpy(g.GetPointData().GetArray("pressure"))
            H, U = 0.41, 0.3
            inflow = np.abs(x[:, 0]) < 1e-12
            walls = (np.abs(x[:, 1]) < 1e-12) | (np.abs(x[:, 1] - H) < 1e-12)
            exact = 4 * U * x[inflow, 1] * (H - x[inflow, 1]) / H**2
            check(inflow.sum() >= 5, f"{f}: {inflow.sum()} inflow nodes")
            check(np.abs(u[inflow, 0] - exact).max() < 1e-12, f"{f}: inflow profile")
            check(np.abs(u[walls, :2]).max() < 1e-12, f"{f}: no-slip walls")
            check(np.isfinite(p).all() and np.ptp(p) > 0, f"{f}: pressure")
    cfd = os.path.join(work, "cfd")
    if run("cases/cfd_dem/fluidized_bed/case.yaml", cfd, "--set", "time.end=0.003", "--set",
           "output.vtk.every=0.001"):
        files = listed(os.path.join(cfd, "fluid.pvd"))
        check(len(files) == 4, f"fluid.pvd lists {len(files)} files, expected 4")
        for f in files:
            g = read(f, vtk.vtkXMLImageDataReader())
            dims = g.GetDimensions()
            check(dims == (9, 3, 31), f"{f}: dimensions {dims}, expected the 8 x 2 x 30 cells + 1")
            eps = vtk_to_numpy(g.GetCellData().GetArray("fluid_fraction"))
            u = vtk_to_numpy(g.GetCellData().GetArray("velocity"))
            p = vtk_to_numpy(g.GetCellData().GetArray("pressure"))
            check(eps.size == 480 and u.shape == (480, 3) and p.size == 480, f"{f}: array sizes")
            check(eps.min() >= 0.3 and eps.max() <= 1.0 and eps.min() < 0.9, f"{f}: fluid fraction")
            check(np.isfinite(u).all() and np.isfinite(p).all(), f"{f}: finite fields")
    if failed:
        print(f"{len(failed)} checks failed (kept {work})")
        return 1
    shutil.rmtree(work, ignore_errors=True)
    print("all checks passed")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
