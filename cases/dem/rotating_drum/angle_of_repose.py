#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-3.0-or-later
# Dynamic angle of repose of the rotating drum from grainflow's particle CSV files.
"""Usage: /usr/bin/python3 angle_of_repose.py OUTPUT_DIR [--skip SECONDS] [--plot FILE.png]
                         [--radius R] [--dt DT] [--up z|y] [--title TEXT]

The free surface is the top of the bed in vertical columns (x bins) across the central 60 % of
the drum diameter; a straight line fitted to the column tops gives the angle with the
horizontal. Each CSV file after --skip gives one angle; their mean and spread are printed."""
import argparse
import glob
import math
import os

import numpy as np

ap = argparse.ArgumentParser()
ap.add_argument("output")
ap.add_argument("--radius", type=float, default=0.1, help="drum radius (m)")
ap.add_argument("--dt", type=float, default=2.0e-5, help="time step, to turn file numbers into times (s)")
ap.add_argument("--skip", type=float, default=1.0, help="ignore snapshots before this time (s)")
ap.add_argument("--plot", help="write a PNG of the last snapshot and its fit")
ap.add_argument("--up", choices=["z", "y"], default="z",
                help="the vertical axis: z (3D drum, axis along y) or y (2D drum)")
ap.add_argument("--title", default="rotating drum, 15 rpm", help="title of the plot")
args = ap.parse_args()

angles = []
last = None
for path in sorted(glob.glob(os.path.join(args.output, "particles_*.csv"))):
    step = int(os.path.basename(path)[len("particles_"):-len(".csv")])
    t = step * args.dt
    if t < args.skip:
        continue
    d = np.genfromtxt(path, delimiter=",", names=True)
    x, z, r = d["x"], d[args.up], d["radius"]
    edges = np.linspace(-0.6 * args.radius, 0.6 * args.radius, 25)
    xs, tops = [], []
    for a, b in zip(edges[:-1], edges[1:]):
        sel = (x >= a) & (x < b)
        if sel.sum() < 3:
            continue
        xs.append(0.5 * (a + b))
        tops.append(np.max(z[sel] + r[sel]))
    slope, icpt = np.polyfit(xs, tops, 1)
    angle = math.degrees(math.atan(abs(slope)))
    angles.append(angle)
    last = (x, z, xs, tops, slope, icpt, t, angle)
    print(f"t = {t:.2f} s: angle {angle:.1f} deg")

if not angles:
    raise SystemExit("no snapshot after --skip")
a = np.array(angles)
print(f"dynamic angle of repose: {a.mean():.1f} deg (std {a.std():.1f}, {len(a)} snapshots)")
if args.plot and last:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    x, z, xs, tops, slope, icpt, t, angle = last
    fig, ax = plt.subplots(figsize=(5, 5))
    ax.plot(x, z, ".", ms=1)
    phi = np.linspace(0, 2 * np.pi, 200)
    ax.plot(args.radius * np.cos(phi), args.radius * np.sin(phi), "k-", lw=0.8)
    xx = np.array([xs[0], xs[-1]])
    ax.plot(xx, slope * xx + icpt, "r-", label=f"fit: {angle:.1f} deg")
    ax.set_aspect("equal")
    ax.set_title(f"{args.title}, t = {t:.2f} s")
    ax.legend()
    fig.savefig(args.plot, dpi=120)
