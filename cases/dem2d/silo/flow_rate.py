#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""Mass flow rate of a silo run against Beverloo's law (2D, or 3D with --dimension 3).

Usage: /usr/bin/python3 flow_rate.py OUTPUT_DIR [--dimension 2] [--outlet below] [--from 0.5]
           [--orifice 0.016] [--grain 0.002] [--depth 0.002] [--density 2500]
           [--solid-fraction 0.82] [--k 1.5] [--plot FILE]

Reads OUTPUT_DIR/series.csv (columns time and outlet_mass.OUTLET), fits a line to the outlet's
mass from --from seconds on (the steady flow of a recirculated silo) and prints the rate W, its
value over the window's two halves, and Beverloo's C for the given k:
2D: W = C rho_b sqrt(g) t (D - k d)^(3/2), t the layer's depth (domain.thickness);
3D: W = C rho_b sqrt(g) (D - k d)^(5/2) (C = 0.58 in Beverloo et al. 1961);
rho_b = solid fraction x density."""
import argparse
import math
import os

import numpy as np

ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawTextHelpFormatter)
ap.add_argument("output")
ap.add_argument("--dimension", type=int, choices=(2, 3), default=2)
ap.add_argument("--outlet", default="below")
ap.add_argument("--from", dest="start", type=float, default=0.5, help="window start, s")
ap.add_argument("--orifice", type=float, default=0.016, help="D, m")
ap.add_argument("--grain", type=float, default=0.002, help="mean grain diameter d, m")
ap.add_argument("--depth", type=float, default=0.002, help="domain.thickness t, m")
ap.add_argument("--density", type=float, default=2500.0, help="grain density, kg/m^3")
ap.add_argument("--solid-fraction", type=float, default=0.82, help="of the bed")
ap.add_argument("--k", type=float, default=1.5)
ap.add_argument("--plot", help="PNG of the outlet's mass against time")
a = ap.parse_args()

path = os.path.join(a.output, "series.csv")
d = np.genfromtxt(path, delimiter=",", names=True, deletechars="")
column = f"outlet_mass.{a.outlet}"
if column not in d.dtype.names:
    raise SystemExit(f"{path}: no column '{column}' (series quantities: {', '.join(d.dtype.names)})")
t, m = d["time"], d[column]
w = t >= a.start
if w.sum() < 4:
    raise SystemExit(f"{path}: fewer than 4 rows from t = {a.start} s on")
rate = np.polyfit(t[w], m[w], 1)[0]
tw, mw = t[w], m[w]
h = len(tw) // 2
first, second = np.polyfit(tw[:h], mw[:h], 1)[0], np.polyfit(tw[h:], mw[h:], 1)[0]
rho_b = a.solid_fraction * a.density
if a.dimension == 2:
    c = rate / (rho_b * math.sqrt(9.81) * a.depth * (a.orifice - a.k * a.grain) ** 1.5)
else:
    c = rate / (rho_b * math.sqrt(9.81) * (a.orifice - a.k * a.grain) ** 2.5)
print(f"window {tw[0]:.3f}-{tw[-1]:.3f} s: W = {1e3 * rate:.3f} g/s "
      f"(halves {1e3 * first:.3f}, {1e3 * second:.3f})")
depth = f", t = {a.depth * 1e3:g} mm" if a.dimension == 2 else ""
print(f"Beverloo ({a.dimension}D) with k = {a.k}: C = {c:.3f} (rho_b = {rho_b:.0f} kg/m^3, "
      f"D = {a.orifice * 1e3:g} mm, d = {a.grain * 1e3:g} mm{depth})")
if a.plot:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(5.5, 4))
    ax.plot(t, m * 1e3, "-", label=f"outlet '{a.outlet}'")
    ax.plot(tw, (np.polyval(np.polyfit(tw, mw, 1), tw)) * 1e3, "k--", lw=0.8,
            label=f"W = {1e3 * rate:.2f} g/s")
    ax.set_xlabel("t (s)")
    ax.set_ylabel("mass through the outlet (g)")
    ax.legend()
    fig.tight_layout()
    fig.savefig(a.plot, dpi=120)
