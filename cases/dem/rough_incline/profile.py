#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-3.0-or-later
# Flow on the rough incline: velocity profile, surface speed and basal friction from a run.
"""Usage: /usr/bin/python3 profile.py OUTPUT_DIR [--skip SECONDS]

Reads the particle CSV files (particles_*.csv, with their `fixed` column) written after --skip
and the series (series.csv) of a rough_incline run:
  - the bed top z_b (highest fixed centre + its radius) and the flow's free surface z_s (the
    95th percentile of the free grains' tops), the flow depth H = z_s - z_b in diameters;
  - the mean downslope velocity u(z) and solid fraction in layers one mean diameter thick,
    averaged over the snapshots;
  - the surface speed u_s (mean u of the grains whose centre lies within one diameter of z_s),
    the depth-averaged speed, and the fit of Bagnold's profile u = u_s (1 - (1 - zeta)^(3/2)),
    zeta = (z - z_b) / H, to the layers below the surface;
  - from the series: the kinetic energy at the start and end of the window (steadiness) and the
    basal friction fixed_force.x / -fixed_force.z against tan(theta) from the gravity.
"""
import argparse
import glob
import math
import os
import re

import numpy as np

ap = argparse.ArgumentParser()
ap.add_argument("output")
ap.add_argument("--skip", type=float, default=2.0, help="ignore snapshots before this time (s)")
args = ap.parse_args()

resolved = open(os.path.join(args.output, "resolved_case.yaml")).read()
dt = float(re.search(r"time: \{step: ([0-9.e+-]+)", resolved).group(1))
g = [float(v) for v in re.search(r"gravity: \[([^\]]+)\]", resolved).group(1).split(",")]
lo = [float(v) for v in re.search(r"domain: \{min: \[([^\]]+)\]", resolved).group(1).split(",")]
hi = [float(v) for v in re.search(r"max: \[([^\]]+)\]", resolved).group(1).split(",")]
area = (hi[0] - lo[0]) * (hi[1] - lo[1])
theta = math.degrees(math.atan2(g[0], -g[2]))

snaps = []
for path in sorted(glob.glob(os.path.join(args.output, "particles_*.csv"))):
    t = int(os.path.basename(path)[len("particles_"):-len(".csv")]) * dt
    if t >= args.skip - 1e-9:
        snaps.append((t, np.genfromtxt(path, delimiter=",", names=True)))
if not snaps:
    raise SystemExit(f"no particle files after t = {args.skip} s in {args.output}")

d = 2 * np.mean(snaps[0][1]["radius"][snaps[0][1]["fixed"] == 0])
z_b = max(np.max(s["z"][s["fixed"] == 1] + s["radius"][s["fixed"] == 1]) for _, s in snaps)
tops = [np.percentile(s["z"][s["fixed"] == 0] + s["radius"][s["fixed"] == 0], 95) for _, s in snaps]
z_s = float(np.mean(tops))
H = z_s - z_b
edges = np.arange(z_b, z_s + d, d)
u_sum = np.zeros(len(edges) - 1)
n_sum = np.zeros(len(edges) - 1)
phi_sum = np.zeros(len(edges) - 1)
surface, mean_u = [], []
for _, s in snaps:
    free = s["fixed"] == 0
    z, u, r = s["z"][free], s["vx"][free], s["radius"][free]
    mean_u.append(np.mean(u))
    top = np.percentile(z + r, 95)
    surface.append(np.mean(u[z > top - 1.5 * d]))  # centres within a diameter of the surface
    k = np.digitize(z, edges) - 1
    ok = (k >= 0) & (k < len(u_sum))
    np.add.at(u_sum, k[ok], u[ok])
    np.add.at(n_sum, k[ok], 1)
    np.add.at(phi_sum, k[ok], 4.0 / 3.0 * math.pi * r[ok] ** 3 / (area * d))
u_prof = np.where(n_sum > 0, u_sum / np.maximum(n_sum, 1), np.nan)
phi = phi_sum / len(snaps)
u_s = float(np.mean(surface))

print(f"run {args.output}: theta = {theta:.2f} deg, {len(snaps)} snapshots from t = "
      f"{snaps[0][0]:.2f} s to {snaps[-1][0]:.2f} s")
print(f"bed top z_b = {1e3 * z_b:.2f} mm, surface z_s = {1e3 * z_s:.2f} mm, depth H = "
      f"{1e3 * H:.2f} mm = {H / d:.1f} d (d = {1e3 * d:.2f} mm)")
print("layer (z - z_b)/d   u (m/s)   solid fraction   Bagnold u_s (1 - (1 - zeta)^1.5)")
for i in range(len(u_prof)):
    zc = 0.5 * (edges[i] + edges[i + 1])
    zeta = min(max((zc - z_b) / H, 0.0), 1.0)
    print(f"  {(zc - z_b) / d:6.2f}          {u_prof[i]:8.4f}   {phi[i]:6.3f}           "
          f"{u_s * (1 - (1 - zeta) ** 1.5):8.4f}")
print(f"surface speed u_s = {u_s:.4f} m/s (snapshots: {min(surface):.4f} .. {max(surface):.4f})")
print(f"depth-averaged speed = {np.mean(mean_u):.4f} m/s; u_s / sqrt(g d) = "
      f"{u_s / math.sqrt(9.81 * d):.2f}")

series = np.genfromtxt(os.path.join(args.output, "series.csv"), delimiter=",", names=True)
w = series["time"] >= args.skip - 1e-9
if np.any(w):
    fx, fz = series["fixed_forcex"][w], series["fixed_forcez"][w]
    ek = series["kinetic_energy"][w]
    print(f"basal friction <fixed_force.x> / <-fixed_force.z> = {np.mean(fx) / -np.mean(fz):.4f}, "
          f"tan(theta) = {math.tan(math.radians(theta)):.4f}")
    print(f"kinetic energy: {ek[0]:.4e} J at t = {series['time'][w][0]:.2f} s, "
          f"{ek[-1]:.4e} J at t = {series['time'][w][-1]:.2f} s (window mean {np.mean(ek):.4e} J)")
