#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-3.0-or-later
# Angle of repose of a 2D heap from grainflow's last particle CSV file.
"""Usage: /usr/bin/python3 heap_angle.py OUTPUT_DIR [OUTPUT_DIR ...] [--plot FILE.png]

The heap's surface is the top of the pile (y + bounding radius of the highest grain) in
vertical columns two mean diameters wide. On each flank the columns between 20 % and 80 % of
the heap height are fitted with a straight line; the angle of repose is the mean of the flank
angles with the horizontal. A pile leaning on a wall (the shipped cases: the grains left behind
when a gate is pulled away) has one flank only, which is then the measurement. Several output
folders (e.g. polygons and disks) are compared on one plot."""
import argparse
import glob
import math
import os

import numpy as np


def last_csv(folder):
    files = sorted(glob.glob(os.path.join(folder, "particles_*.csv")))
    if not files:
        raise SystemExit(f"no particles_*.csv in {folder}")
    return files[-1]


def heap_angle(path):
    d = np.genfromtxt(path, delimiter=",", names=True)
    x, y, r = d["x"], d["y"], d["radius"]
    width = 4.0 * np.mean(r)
    edges = np.arange(x.min(), x.max() + width, width)
    xs, tops = [], []
    for a, b in zip(edges[:-1], edges[1:]):
        sel = (x >= a) & (x < b)
        if sel.sum() == 0:
            continue
        xs.append(0.5 * (a + b))
        tops.append(np.max(y[sel] + r[sel]))
    xs, tops = np.array(xs), np.array(tops)
    h = tops.max()
    peak = xs[np.argmax(tops)]
    out = {}
    for side, mask in (("left", xs < peak), ("right", xs > peak)):
        sel = mask & (tops > 0.2 * h) & (tops < 0.8 * h)
        if sel.sum() < 3:
            continue  # no flank on this side (a pile against a wall)
        slope, icpt = np.polyfit(xs[sel], tops[sel], 1)
        out[side] = (math.degrees(math.atan(abs(slope))), slope, icpt, xs[sel], tops[sel])
    if not out:
        raise SystemExit(f"{path}: too few columns on either flank to fit a slope")
    return x, y, r, xs, tops, out


ap = argparse.ArgumentParser()
ap.add_argument("outputs", nargs="+")
ap.add_argument("--plot", help="write a PNG of the heaps and their fits")
args = ap.parse_args()

results = []
for folder in args.outputs:
    path = last_csv(folder)
    x, y, r, xs, tops, fit = heap_angle(path)
    angles = {side: f[0] for side, f in fit.items()}
    mean = sum(angles.values()) / len(angles)
    flanks = ", ".join(f"{side} {a:.1f}" for side, a in angles.items())
    print(f"{folder}: angle of repose {mean:.1f} deg ({flanks}; {len(x)} grains, height "
          f"{tops.max() * 1000:.1f} mm, file {os.path.basename(path)})")
    results.append((folder, x, y, r, xs, tops, fit, mean))

if args.plot:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(len(results), 1, figsize=(7, 2.6 * len(results)), squeeze=False)
    for ax, (folder, x, y, r, xs, tops, fit, mean) in zip(axes[:, 0], results):
        ax.scatter(x, y, s=1, c="0.6")
        ax.plot(xs, tops, "k-", lw=0.8, label="surface")
        for side in fit:
            ang, slope, icpt, fx, _ = fit[side]
            ax.plot(fx, slope * fx + icpt, "r-", lw=2)
        ax.set_title(f"{os.path.basename(os.path.normpath(folder))}: {mean:.1f} deg")
        ax.set_aspect("equal")
        ax.set_xlabel("x (m)")
        ax.set_ylabel("y (m)")
    fig.tight_layout()
    fig.savefig(args.plot, dpi=130)
    print(f"plot written to {args.plot}")
