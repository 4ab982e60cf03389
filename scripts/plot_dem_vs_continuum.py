#!/usr/bin/python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""Grains against their continuum: DEM and mu(I) SPH for the same column collapse and dam break.

Usage:
  /usr/bin/python3 scripts/plot_dem_vs_continuum.py [--out DIR] [--tables DIR]
  /usr/bin/python3 scripts/plot_dem_vs_continuum.py --extract TABLE_DIR \\
      --calibration SWEEP_DIR --dem-collapse RUN --sph-collapse RUN --dem-dam RUN --sph-dam RUN

Plot mode (the default) reads three tables from --tables (default docs/validation) and writes
continuum_vs_dem.png into --out (default docs/validation):
  continuum_mu_i_calibration.csv  the (I, mu) points of the Lees-Edwards sweep of
                                  cases/rheology/mu_i_calibration and the fitted mu(I);
  continuum_vs_dem_collapse.csv   front and top of the collapsing column over time;
  continuum_vs_dem_deposit.csv    the surface of its deposit at rest;
  continuum_vs_dem_dam_break.csv  force on the cylinder per metre of depth over time.
Extract mode writes those tables from the output folders of
  grainflow sweep cases/rheology/mu_i_calibration/case.yaml          (--calibration)
  grainflow run cases/dem/column_collapse/case.yaml                  (--dem-collapse)
  grainflow run cases/continuum/column_collapse/case.yaml            (--sph-collapse)
  grainflow run cases/dem/granular_dam_break/case.yaml               (--dem-dam)
  grainflow run cases/continuum/granular_dam_break/case.yaml         (--sph-dam)
Times are counted from the release: the DEM column settles first and its gate opens at
t = 0.4 s; the SPH column starts at rest at t = 0. The DEM front is the end of the contiguous
deposit (grains beyond a gap of four diameters are left out), its top the highest grain within
2 cm of the back wall; the SPH front and top are max_x and the highest particle near the wall.
DEM forces are divided by the slab's depth (periodic along y). Uses Debian's python3-numpy and
python3-matplotlib."""
import argparse
import csv
import glob
import os
import re

import numpy as np

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

RELEASE_DEM = 0.4  # s, the gate of the DEM cases opens
GRAIN_DENSITY = 2500.0  # kg/m^3, as in the cases
DIAMETER = 0.003  # m, the calibration's spheres
SPH_SPACING = 0.0025  # m, dx of the SPH cases (a particle's top is half of it above its centre)


def mu_i(i, mu_s, mu_2, i0):
    return mu_s + (mu_2 - mu_s) * i / (i0 + i)


def fit_mu_i(i, mu):
    """Least-squares fit of mu(I) = mu_s + (mu_2 - mu_s) / (1 + I0 / I): a grid over (mu_s, I0),
    mu_2 - mu_s linear in between."""
    best = None
    for ms in np.linspace(0.0, 1.0, 1001):
        for i0 in np.geomspace(1e-3, 10.0, 400):
            x = i / (i + i0)
            dm = np.sum((mu - ms) * x) / np.sum(x * x)
            res = np.sum((ms + dm * x - mu) ** 2)
            if best is None or res < best[0]:
                best = (res, ms, ms + dm, i0)
    return best[1], best[2], best[3], np.sqrt(best[0] / len(i))


def particles_step(path):
    return int(re.search(r"_(\d+)\.csv$", path).group(1))


def dem_front_top(run):
    """(t, front, top) per particles_*.csv of a DEM run folder (x along the flow, z up)."""
    with open(os.path.join(run, "resolved_case.yaml")) as f:
        step = float(re.search(r"step:\s*([0-9.eE+-]+)", f.read()).group(1))
    rows = []
    for path in sorted(glob.glob(os.path.join(run, "particles_*.csv")), key=particles_step):
        a = np.genfromtxt(path, delimiter=",", names=True)
        t = particles_step(path) * step - RELEASE_DEM
        if t < -1e-9:
            continue
        ends = np.sort(a["x"] + a["radius"])
        gaps = np.nonzero(np.diff(ends) > 8 * a["radius"].mean())[0]
        front = ends[gaps[0]] if len(gaps) else ends[-1]
        top = (a["z"] + a["radius"])[a["x"] < 0.02].max()
        rows.append((t, front, top))
    return rows


def sph_front_top(run):
    """(t, front, top) per sph_particles_*.vtp of an SPH run (vtk from Debian's python3-vtk)."""
    times = {}
    with open(os.path.join(run, "sph_particles.pvd")) as f:
        for m in re.finditer(r'timestep="([^"]+)"[^>]*file="([^"]+)"', f.read()):
            times[m.group(2)] = float(m.group(1))
    rows = []
    for name, t in sorted(times.items(), key=lambda kv: kv[1]):
        g = sph_points(run, name)
        top = g[:, 1][g[:, 0] < 0.02].max()
        rows.append((t, g[:, 0].max(), top))
    return rows


BIN = 0.005  # m, width of the columns the deposit's surface is measured in


def last_file(run, pattern, key):
    return sorted(glob.glob(os.path.join(run, pattern)), key=key)[-1]


def surface(x, top, lo=0.0):
    """(x, h) of the highest point in each column of width BIN, from lo to the last point."""
    edges = np.arange(lo, x.max() + BIN, BIN)
    rows = []
    for a, b in zip(edges[:-1], edges[1:]):
        m = (x >= a) & (x < b)
        if m.any():
            rows.append((0.5 * (a + b), top[m].max()))
    return rows


def dem_deposit(run):
    a = np.genfromtxt(last_file(run, "particles_*.csv", particles_step), delimiter=",", names=True)
    return surface(a["x"], a["z"] + a["radius"])


def sph_points(run, name):
    from vtkmodules.util.numpy_support import vtk_to_numpy
    from vtkmodules.vtkIOXML import vtkXMLPolyDataReader

    r = vtkXMLPolyDataReader()
    r.SetFileName(os.path.join(run, name))
    r.Update()
    out = r.GetOutput()
    x = vtk_to_numpy(out.GetPoints().GetData())
    wall = vtk_to_numpy(out.GetPointData().GetArray("wall"))
    return x[wall < 0]


def sph_deposit(run, spacing):
    name = os.path.basename(last_file(run, "sph_particles_*.vtp", lambda p: p))
    g = sph_points(run, name)
    return surface(g[:, 0], g[:, 1] + 0.5 * spacing)


def dem_force(run, wall="cylinder"):
    a = np.genfromtxt(os.path.join(run, "series.csv"), delimiter=",", names=True)
    with open(os.path.join(run, "resolved_case.yaml")) as f:
        text = f.read()
    lo, hi = (re.search(r"%s:\s*\[([^\]]+)\]" % k, text).group(1) for k in ("min", "max"))
    depth = float(hi.split(",")[1]) - float(lo.split(",")[1])
    key = "wall_force%s" % wall
    return [(t - RELEASE_DEM, fx / depth, fz / depth)
            for t, fx, fz in zip(a["time"], a[key + "x"], a[key + "z"]) if t >= RELEASE_DEM]


def sph_force(run, wall="cylinder"):
    a = np.genfromtxt(os.path.join(run, "sph_series.csv"), delimiter=",", names=True)
    return list(zip(a["time"], a["force_x" + wall], a["force_y" + wall]))


def write(path, header, rows):
    with open(path, "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(header)
        for r in rows:
            w.writerow([r[0]] + ["%.6g" % v for v in r[1:]])


def extract(args):
    os.makedirs(args.extract, exist_ok=True)
    sweep = list(csv.DictReader(open(os.path.join(args.calibration, "sweep.csv"))))
    pts = []
    for r in sweep:
        p, rate = float(r["pressure"]), abs(float(r["shear_rate"]))
        pts.append((r["run"], float(r["volume_fraction"]), rate, p,
                    rate * DIAMETER / np.sqrt(p / GRAIN_DENSITY), float(r["friction"]),
                    float(r["friction_err"])))
    write(os.path.join(args.extract, "continuum_mu_i_calibration.csv"),
          ["run", "volume_fraction", "shear_rate", "pressure", "inertial_number", "friction",
           "friction_err"], pts)
    write(os.path.join(args.extract, "continuum_vs_dem_collapse.csv"),
          ["model", "t", "front", "top"],
          [("dem",) + r for r in dem_front_top(args.dem_collapse)] +
          [("sph",) + r for r in sph_front_top(args.sph_collapse)])
    write(os.path.join(args.extract, "continuum_vs_dem_deposit.csv"), ["model", "x", "h"],
          [("dem",) + r for r in dem_deposit(args.dem_collapse)] +
          [("sph",) + r for r in sph_deposit(args.sph_collapse, SPH_SPACING)])
    write(os.path.join(args.extract, "continuum_vs_dem_dam_break.csv"),
          ["model", "t", "force_x", "force_z"],
          [("dem",) + r for r in dem_force(args.dem_dam)] +
          [("sph",) + r for r in sph_force(args.sph_dam)])


def table(folder, name):
    return np.genfromtxt(os.path.join(folder, name), delimiter=",", names=True, dtype=None,
                         encoding="utf-8")


def smooth(t, y, width):
    """Mean of y over windows of `width` seconds (the DEM force is a sum of impacts)."""
    edges = np.arange(t.min(), t.max() + width, width)
    idx = np.digitize(t, edges)
    tt = np.array([t[idx == k].mean() for k in np.unique(idx)])
    yy = np.array([y[idx == k].mean() for k in np.unique(idx)])
    return tt, yy


def finish(a, xlabel, ylabel, title):
    a.set_xlabel(xlabel)
    a.set_ylabel(ylabel)
    a.set_title(title, fontsize=9)
    a.legend(fontsize=7)


def plot(args):
    cal = table(args.tables, "continuum_mu_i_calibration.csv")
    col = table(args.tables, "continuum_vs_dem_collapse.csv")
    dam = table(args.tables, "continuum_vs_dem_dam_break.csv")
    dep = table(args.tables, "continuum_vs_dem_deposit.csv")
    ms, m2, i0, rms = fit_mu_i(cal["inertial_number"], cal["friction"])
    fig, ax = plt.subplots(1, 4, figsize=(19, 4.3))
    a = ax[0]
    a.errorbar(cal["inertial_number"], cal["friction"], yerr=cal["friction_err"], fmt="o",
               label="DEM, Lees-Edwards shear at fixed phi")
    ii = np.geomspace(cal["inertial_number"].min() / 2, cal["inertial_number"].max() * 1.5, 100)
    a.plot(ii, mu_i(ii, ms, m2, i0), "k-", lw=0.8,
           label="fit: mu_s %.3f, mu_2 %.3f, I0 %.3f" % (ms, m2, i0))
    a.set_xscale("log")
    finish(a, "I = gamma_dot d / sqrt(P / rho_s)", "mu = |sigma_xz| / P",
           "mu(I) of the DEM grains (glass spheres, friction 0.5)")
    a = ax[1]
    for model, style, name in (("dem", "o", "DEM (5300 spheres)"),
                               ("sph", "-", "SPH, mu(I) from the fit")):
        d = col[col["model"] == model]
        a.plot(d["t"], d["front"], style, ms=4, label=name + ": front")
        a.plot(d["t"], d["top"], style, ms=4, mfc="none", label=name + ": top at the wall")
    finish(a, "t since release (s)", "x of the front, height of the top (m)",
           "Column collapse, L0 = 0.1 m, H0 = 0.115 m")
    a = ax[2]
    for model, style, name in (("dem", "o", "DEM: highest grain per 5 mm"),
                               ("sph", "-", "SPH, mu(I): highest particle per 5 mm")):
        d = dep[dep["model"] == model]
        a.plot(d["x"], d["h"], style, ms=3, label=name)
    a.plot([0, 0.1, 0.1], [0.1155, 0.1155, 0], "k:", lw=0.8, label="column at release")
    finish(a, "x (m)", "deposit height (m)", "Deposits at rest")
    a = ax[3]
    for model, name, width in (("dem", "DEM (per m of depth, 5 ms means)", 0.005),
                               ("sph", "SPH mu(I) (5 ms means)", 0.005)):
        d = dam[dam["model"] == model]
        t, fx = smooth(d["t"], d["force_x"], width)
        a.plot(t, fx, "-", label=name + ": x")
        t, fz = smooth(d["t"], d["force_z"], width)
        a.plot(t, fz, "--", label=name + ": vertical")
    finish(a, "t since release (s)", "force on the cylinder (N/m)",
           "Dam break against a cylinder (r = 15 mm at x = 0.2 m)")
    fig.tight_layout()
    os.makedirs(args.out, exist_ok=True)
    fig.savefig(os.path.join(args.out, "continuum_vs_dem.png"), dpi=110)
    print("mu(I) fit: mu_s %.4f mu_2 %.4f I0 %.4f (rms %.4f)" % (ms, m2, i0, rms))


def main():
    here = os.path.dirname(os.path.abspath(__file__))
    docs = os.path.join(here, "..", "docs", "validation")
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawTextHelpFormatter)
    p.add_argument("--out", default=docs)
    p.add_argument("--tables", default=docs)
    p.add_argument("--extract", metavar="TABLE_DIR")
    for k in ("calibration", "dem-collapse", "sph-collapse", "dem-dam", "sph-dam"):
        p.add_argument("--" + k)
    args = p.parse_args()
    if args.extract:
        missing = [k for k in ("calibration", "dem_collapse", "sph_collapse", "dem_dam", "sph_dam")
                   if getattr(args, k) is None]
        if missing:
            p.error("--extract needs " + ", ".join("--" + k.replace("_", "-") for k in missing))
        extract(args)
    else:
        plot(args)


if __name__ == "__main__":
    main()
