#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-3.0-or-later
# Stress-strain curves of the 2D biaxial test from grainflow's series.csv.
"""Usage: /usr/bin/python3 biaxial.py OUTPUT_DIR [OUTPUT_DIR ...] [--start 3.0] [--thickness 0.01]
                                      [--plot FILE.png]

sigma_1 = top-wall force / (width x thickness), sigma_3 = right-wall force / (height x
thickness), width = x of the right wall (the left wall is at x = 0), height = y of the top wall
(the floor is at y = 0); axial strain = (h0 - h) / h0 from the height h0 when the top wall
starts to move (--start, s). Prints the peak stress ratio sigma_1/sigma_3, the mobilised friction
angle at the peak, asin((s1 - s3)/(s1 + s3)), and the ratio at 8-10 % strain (near the critical
state); plots the curves of all folders together."""
import argparse
import math
import os

import numpy as np

ap = argparse.ArgumentParser()
ap.add_argument("outputs", nargs="+")
ap.add_argument("--start", type=float, default=3.0, help="time the axial loading starts (s)")
ap.add_argument("--thickness", type=float, default=0.01, help="domain.thickness (m)")
ap.add_argument("--plot")
args = ap.parse_args()

curves = []
for folder in args.outputs:
    d = np.genfromtxt(os.path.join(folder, "series.csv"), delimiter=",", names=True)
    t = d["time"]
    width, height = d["wall_positionrightx"], d["wall_positiontopy"]
    s1 = d["wall_forcetopy"] / (width * args.thickness)
    s3 = d["wall_forcerightx"] / (height * args.thickness)
    sel = t >= args.start
    if sel.sum() < 10:
        raise SystemExit(f"{folder}: no data after --start {args.start} s")
    h0 = height[sel][0]
    eps = (h0 - height[sel]) / h0
    ratio = s1[sel] / s3[sel]
    k = np.argmax(ratio)
    phi = math.degrees(math.asin((ratio[k] - 1) / (ratio[k] + 1)))
    late = (eps > 0.8 * eps.max())
    print(f"{folder}: sigma_3 before loading {s3[sel][0]:.0f} Pa, sigma_1 {s1[sel][0]:.0f} Pa; peak "
          f"sigma_1/sigma_3 = {ratio[k]:.2f} at strain {100 * eps[k]:.2f} % (friction angle "
          f"{phi:.1f} deg); last 20 % of the strain range: {ratio[late].mean():.2f}; strain reached "
          f"{100 * eps.max():.1f} %")
    curves.append((os.path.basename(os.path.normpath(folder)), eps, ratio))

if args.plot:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(6, 4))
    for name, eps, ratio in curves:
        ax.plot(100 * eps, ratio, label=name)
    ax.set_xlabel("axial strain (%)")
    ax.set_ylabel("stress ratio sigma_1 / sigma_3")
    ax.set_title("2D biaxial compression at sigma_3 = 10 kPa")
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(args.plot, dpi=130)
    print(f"plot written to {args.plot}")
