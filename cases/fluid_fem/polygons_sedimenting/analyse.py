#!/usr/bin/python3
# SPDX-License-Identifier: GPL-3.0-or-later
# Sedimentation fronts and the deposit's slope of cases/fluid_fem/polygons_sedimenting:
#   grainflow run cases/fluid_fem/polygons_sedimenting/case.yaml --output out/polygons_sedimenting
#   /usr/bin/python3 cases/fluid_fem/polygons_sedimenting/analyse.py out/polygons_sedimenting
# (a second argument names another case file with the same kind of bodies)
# prints the speeds of the upper and lower sedimentation fronts and the angle of the deposit's
# free surface, and draws docs/validation/fem/polygons_sedimenting.png (grain outlines at four
# times, the fronts over time, the surface and its fitted slope).
#
# Grain outlines at time t: the case's vertices turned by NAME.angle about the polygon's centroid
# and moved with NAME.x, NAME.y (fem_forces.csv: a free polygon's centre is its centroid).
# Fronts: the highest grain top (upper front) and the lowest grain bottom (lower front); their
# speeds are straight-line fits while they fall freely (between 5 % and 50 % of their total drop).
# Slope: the deposit's surface is the highest grain point in vertical strips one mean grain
# diameter wide; the angle is a straight-line fit of those heights on the heap's flank, from
# the strip of the highest point to the last strip the heap covers (the bare floor beyond is
# left out). With a dozen grains this is the angle of a small heap, one or two grains per strip:
# a measure of the case, not a material's angle of repose.
import os
import re
import sys

import matplotlib
import numpy as np

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(os.path.dirname(HERE)))


def polygons(case_file):
    """{name: (vertices relative to the centroid, centroid)} of the case's polygon bodies."""
    out = {}
    pat = re.compile(r"\{name:\s*(\w+),\s*polygon:\s*(\[\[.*?\]\])")
    for line in open(case_file):
        m = pat.search(line)
        if not m:
            continue
        v = np.array([[float(a), float(b)] for a, b in
                      re.findall(r"\[([-+0-9.eE]+),\s*([-+0-9.eE]+)\]", m.group(2))])
        x, y = v[:, 0], v[:, 1]
        xn, yn = np.roll(x, -1), np.roll(y, -1)
        c = x * yn - xn * y
        area = 0.5 * c.sum()
        centroid = np.array([((x + xn) * c).sum(), ((y + yn) * c).sum()]) / (6 * area)
        out[m.group(1)] = (v - centroid, centroid, abs(area))
    return out


def outline(shape, row, cols, name):
    rel = shape[0]
    a = row[cols[name + ".angle"]]
    rot = np.array([[np.cos(a), -np.sin(a)], [np.sin(a), np.cos(a)]])
    return rel @ rot.T + np.array([row[cols[name + ".x"]], row[cols[name + ".y"]]])


def front_speed(t, h):
    """Speed [m/s] of a falling front h(t), the straight-line fit (slope, intercept) and the index
    range it spans: between 5 % and 50 % of the front's total drop, while it falls freely (later
    it slows where it meets the deposit)."""
    drop = h[0] - h.min()
    if drop <= 0:
        return 0.0, None, (0, 0)
    i0 = int(np.argmax(h <= h[0] - 0.05 * drop))
    i1 = int(np.argmax(h <= h[0] - 0.50 * drop))
    if i1 <= i0 + 1:
        return 0.0, None, (i0, i1)
    fit = np.polyfit(t[i0:i1], h[i0:i1], 1)
    return -fit[0], fit, (i0, i1)


def main(out_dir, case):
    shapes = polygons(case)
    names = sorted(shapes)
    with open(os.path.join(out_dir, "fem_forces.csv")) as f:
        header = f.readline().strip().split(",")
    cols = {c: i for i, c in enumerate(header)}
    data = np.loadtxt(os.path.join(out_dir, "fem_forces.csv"), delimiter=",", skiprows=1)
    t = data[:, cols["t"]]
    tops = np.array([[outline(shapes[n], r, cols, n)[:, 1].max() for n in names] for r in data])
    bottoms = np.array([[outline(shapes[n], r, cols, n)[:, 1].min() for n in names] for r in data])
    upper, lower = tops.max(axis=1), bottoms.min(axis=1)
    u_up, fit_up, (a0, a1) = front_speed(t, upper)
    u_lo, fit_lo, (b0, b1) = front_speed(t, lower)
    # Stokes-like scale: the case's check prints a single grain's settling estimate
    d = 2 * np.sqrt(np.mean([s[2] for s in shapes.values()]) / np.pi)

    final = [outline(shapes[n], data[-1], cols, n) for n in names]
    pts = np.vstack(final)
    xmin, xmax = pts[:, 0].min(), pts[:, 0].max()
    edges = np.arange(0.0, xmax + d, d)
    surf_x, surf_h = [], []
    for lo_e, hi_e in zip(edges[:-1], edges[1:]):
        sel = (pts[:, 0] >= lo_e) & (pts[:, 0] < hi_e)
        if sel.any():
            k = np.argmax(np.where(sel, pts[:, 1], -np.inf))
            surf_x.append(pts[k, 0])
            surf_h.append(pts[k, 1])
    surf_x, surf_h = np.array(surf_x), np.array(surf_h)
    top = int(np.argmax(surf_h))
    flank = slice(top, len(surf_h))
    if len(surf_h[flank]) >= 2:
        slope = np.polyfit(surf_x[flank], surf_h[flank], 1)[0]
    else:
        slope = float("nan")
    angle = np.degrees(np.arctan(abs(slope)))
    speeds = np.hypot(*[data[:, [cols[n + ".vx"] for n in names]],
                        data[:, [cols[n + ".vy"] for n in names]]])
    print(f"grains {len(names)}, mean diameter of equal area d = {1e3 * d:.2f} mm, t_end = {t[-1]:.3f} s")
    print(f"upper front: {1e3 * upper[0]:.1f} -> {1e3 * upper[-1]:.1f} mm, speed {1e3 * u_up:.1f} mm/s "
          f"(fit over t = {t[a0]:.2f}-{t[a1]:.2f} s)")
    print(f"lower front: {1e3 * lower[0]:.1f} -> {1e3 * lower[-1]:.1f} mm, speed {1e3 * u_lo:.1f} mm/s "
          f"(fit over t = {t[b0]:.2f}-{t[b1]:.2f} s)")
    print(f"deposit: spans x = {1e3 * xmin:.1f}-{1e3 * xmax:.1f} mm, height {1e3 * surf_h.max():.1f} mm; "
          f"surface slope {angle:.1f} deg over {len(surf_h[flank])} strips of {1e3 * d:.1f} mm")
    print(f"largest grain speed at the end {1e3 * speeds[-1].max():.3f} mm/s")

    fig, ax = plt.subplots(1, 2, figsize=(11, 4.6))
    a = ax[0]
    for k, frac in enumerate((0.0, 0.2, 0.45, 1.0)):
        i = min(int(frac * (len(t) - 1)), len(t) - 1)
        for j, n in enumerate(names):
            v = outline(shapes[n], data[i], cols, n)
            a.fill(1e3 * v[:, 0], 1e3 * v[:, 1], color=f"C{k}", alpha=0.25 + 0.5 * (k == 3),
                   label=f"t = {t[i]:.2f} s" if j == 0 else None)
    a.plot(1e3 * surf_x[flank], 1e3 * np.polyval(np.polyfit(surf_x[flank], surf_h[flank], 1),
                                                 surf_x[flank]), "k--",
           label=f"surface fit: {angle:.1f} deg")
    a.plot(1e3 * surf_x, 1e3 * surf_h, "k.", ms=4)
    a.set_xlim(0, 60)
    a.set_ylim(0, 50)
    a.set_aspect("equal")
    a.set_xlabel("x [mm]")
    a.set_ylabel("y [mm]")
    a.set_title(f"{len(names)} polygons sedimenting (mu = 0.5 on the film)")
    a.legend(fontsize=7, loc="upper right")
    a = ax[1]
    a.plot(t, 1e3 * upper, label=f"upper front ({1e3 * u_up:.1f} mm/s)")
    a.plot(t, 1e3 * lower, label=f"lower front ({1e3 * u_lo:.1f} mm/s)")
    for fit, (i0, i1), label in ((fit_up, (a0, a1), None), (fit_lo, (b0, b1), "fits")):
        if fit is not None:
            a.plot(t[i0:i1], 1e3 * np.polyval(fit, t[i0:i1]), "k:", lw=1.5, label=label)
    a.set_xlabel("t [s]")
    a.set_ylabel("height [mm]")
    a.set_title("sedimentation fronts")
    a.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(os.path.join(ROOT, "docs", "validation", "fem", "polygons_sedimenting.png"), dpi=110)


if __name__ == "__main__":
    main(sys.argv[1] if len(sys.argv) > 1 else "out/polygons_sedimenting",
         sys.argv[2] if len(sys.argv) > 2 else os.path.join(HERE, "case.yaml"))
