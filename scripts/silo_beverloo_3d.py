#!/usr/bin/python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""Beverloo's law in 3D from the silo of cases/dem/silo, run with several orifices.

Usage: /usr/bin/python3 scripts/silo_beverloo_3d.py [--orifices 5,6,7,8] [--end 1.3]
           [--threads 2] [--grainflow build/release/grainflow] [--plot FILE] [--keep DIR]

For each orifice D (in grain diameters d = 4 mm) it writes the floor's STL
(make_silo_floor_stl.py), runs cases/dem/silo with that floor (the grains recirculated: steady
flow), fits the outlet's mass from 0.6 s to the end (the gate opens at 0.4 s), and then fits
W^(2/5) = a D + b: Beverloo's W = C rho_b sqrt(g) (D - k d)^(5/2) gives k = -b / (a d) and
C = a^(5/2) / (rho_b sqrt(g)), rho_b = 0.588 x 2500 kg/m^3 (the bed's solid fraction measured in
cases/dem/silo). Minutes per orifice."""
import argparse
import math
import os
import subprocess
import sys
import tempfile

import numpy as np

HERE = os.path.dirname(os.path.realpath(__file__))
ROOT = os.path.normpath(os.path.join(HERE, os.pardir))
sys.path.insert(0, HERE)
from make_drum_stl import write_binary_stl  # noqa: E402
from make_silo_floor_stl import floor_triangles  # noqa: E402

D_GRAIN, RHO_B, G = 0.004, 0.588 * 2500.0, 9.81


def rate(series, start):
    d = np.genfromtxt(series, delimiter=",", names=True, deletechars="")
    t, m = d["time"], d["outlet_mass.below"]
    w = t >= start
    return np.polyfit(t[w], m[w], 1)[0]


def main():
    ap = argparse.ArgumentParser(description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--orifices", default="5,6,7,8", help="D / d, comma-separated")
    ap.add_argument("--end", type=float, default=1.3, help="simulated time per run, s")
    ap.add_argument("--threads", type=int, default=2)
    ap.add_argument("--grainflow", default=os.path.join(ROOT, "build", "release", "grainflow"))
    ap.add_argument("--plot", help="PNG of W^(2/5) against D")
    ap.add_argument("--keep", help="folder for the runs (default: a temporary one)")
    a = ap.parse_args()
    ratios = [float(x) for x in a.orifices.split(",")]
    work = a.keep or tempfile.mkdtemp(prefix="silo3d_")
    os.makedirs(work, exist_ok=True)
    case = os.path.join(ROOT, "cases", "dem", "silo", "case.yaml")
    rates = []
    for q in ratios:
        tag = f"D{q:g}"
        stl = os.path.join(work, tag + ".stl")
        write_binary_stl(stl, floor_triangles(0.5 * q * D_GRAIN, 0.036, 64), f"silo floor {tag}")
        out = os.path.join(work, tag)
        cmd = [a.grainflow, "run", case, "--output", out, "--overwrite", "--quiet",
               "--threads", str(a.threads), "--set", f"walls[1].mesh.file={stl}",
               "--set", f"time.end={a.end}", "--set", "output.vtk.every=0",
               "--set", "output.checkpoint.every=0"]
        subprocess.run(cmd, check=True)
        w = rate(os.path.join(out, "series.csv"), 0.6)
        rates.append(w)
        print(f"D = {q:g} d = {q * D_GRAIN * 1e3:g} mm: W = {w * 1e3:.2f} g/s", flush=True)
    dd = np.array(ratios) * D_GRAIN
    w25 = np.array(rates) ** 0.4
    slope, icpt = np.polyfit(dd, w25, 1)
    k = -icpt / slope / D_GRAIN
    c = slope ** 2.5 / (RHO_B * math.sqrt(G))
    resid = np.array(rates) / (slope * dd + icpt) ** 2.5 - 1
    print(f"Beverloo 3D: k = {k:.3f}, C = {c:.3f} (Beverloo et al.: 0.55-0.65, k ~ 1.5); "
          f"rates against the line: {', '.join(f'{100 * r:+.1f} %' for r in resid)}")
    if a.plot:
        import matplotlib

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt

        fig, ax = plt.subplots(figsize=(5.5, 4))
        line = np.linspace(k * D_GRAIN, dd.max() * 1.05, 50)
        ax.plot(np.array(ratios), w25, "o", label="grainflow, 3D silo (cases/dem/silo)")
        ax.plot(line / D_GRAIN, slope * line + icpt, "k-", lw=0.8,
                label=f"Beverloo: C = {c:.2f}, k = {k:.2f}")
        ax.plot(line / D_GRAIN, (0.58 * RHO_B * math.sqrt(G)) ** 0.4 * (line - 1.5 * D_GRAIN),
                "r--", lw=0.8, label="Beverloo et al. (1961): C = 0.58, k = 1.5")
        ax.set_xlim(0, None)
        ax.set_ylim(0, None)
        ax.set_xlabel("orifice D / grain diameter d")
        ax.set_ylabel("W^(2/5) (kg/s)^(2/5)")
        ax.legend(fontsize=7)
        fig.tight_layout()
        fig.savefig(a.plot, dpi=120)


if __name__ == "__main__":
    main()
