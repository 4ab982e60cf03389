#!/usr/bin/python3
# SPDX-License-Identifier: GPL-3.0-or-later
# Plots of the moving-body validations of fluid_fem (free bodies, ALE mesh motion, remeshing,
# repulsion, friction) from the series written by the bench driver:
#   build/release/tests/fem/gf_fem_bench_moving bench/fem/runs
#   /usr/bin/python3 docs/validation/fem/plot_moving.py bench/fem/runs
# writes docs/validation/fem/moving_bodies.png.
import os
import re
import sys

import matplotlib
import numpy as np

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

HERE = os.path.dirname(os.path.abspath(__file__))


def load(folder, name):
    path = os.path.join(folder, name)
    with open(path) as f:
        reference = float(re.findall(r"[-+]?\d+\.\d+(?:[eE][-+]?\d+)?", f.readline())[-1])
    data = np.genfromtxt(path, delimiter=",", skip_header=1, names=True)
    return data, reference


def main(folder):
    fig, ax = plt.subplots(3, 2, figsize=(10, 10.5))

    d, ut = load(folder, "moving_stokes.csv")
    a = ax[0, 0]
    a.plot(d["t"], -d["vy"] / ut, label="free disk, moving mesh")
    a.axhline(1.0, color="k", ls=":", label="Faxen (1946) between walls")
    a.set_ylim(0, 1.1)
    a.set_xlabel("t [s]")
    a.set_ylabel("settling speed / U_t")
    a.set_title(f"Stokes settling, k = 0.2: U(1 s)/U_t = {-d['vy'][-1] / ut:.5f}")
    a.legend(fontsize=8)

    d, us = load(folder, "moving_re10.csv")
    a = ax[0, 1]
    a.plot(d["t"], -d["vy"], label=f"free disk ({int(d['remeshes'][-1])} remeshes)")
    a.axhline(us, color="k", ls=":", label="steady flow in the disk's frame")
    a.set_xlabel("t [s]")
    a.set_ylabel("settling speed [m/s]")
    a.set_title(f"Re = {us * 0.2 / 0.02:.1f}: U(2 s)/U* = {-d['vy'][-1] / us:.5f}")
    a.legend(fontsize=8)

    d, gap = load(folder, "moving_floor_disk.csv")
    a = ax[1, 0]
    a.plot(d["t"], d["y"] - 0.1, label="gap to the floor")
    a.axhline(gap, color="k", ls=":", label="repulsion = buoyant weight")
    a.set_yscale("log")
    a.set_xlabel("t [s]")
    a.set_ylabel("gap [m]")
    a.set_title(f"disk onto the floor: final gap {d['y'][-1] - 0.1:.5f} m")
    a.legend(fontsize=8)

    d, gap = load(folder, "moving_floor_square.csv")
    a = ax[1, 1]
    a.plot(d["t"], np.degrees(d["angle"] + 0.3), label="tilt [deg]")
    a.set_xlabel("t [s]")
    a.set_ylabel("tilt [deg]")
    b = a.twinx()
    b.plot(d["t"], d["y"] - 0.1, color="C1", label="centre height - 0.1 [m]")
    b.axhline(gap, color="C1", ls=":", label="balance when flat")
    b.set_ylim(0, 0.35)
    b.set_ylabel("height above flat contact [m]")
    a.set_title(f"square released at 17 deg: final tilt {np.degrees(d['angle'][-1] + 0.3):.1e} deg")
    h1, l1 = a.get_legend_handles_labels()
    h2, l2 = b.get_legend_handles_labels()
    a.legend(h1 + h2, l1 + l2, fontsize=8)

    # Coulomb friction on a slope (gravity tilted): holds below the friction angle, slides above
    for col, name in ((0, "hold"), (1, "slide")):
        d, ratio = load(folder, f"moving_slope_{name}.csv")
        a = ax[2, col]
        tan_s = ratio * 0.5
        cos_s = 1 / np.sqrt(1 + tan_s**2)
        w = 0.4
        a.plot(d["t"], -d["fx"] / w, label="friction / W")
        a.plot(d["t"], d["fy"] / w, label="normal load / W")
        a.axhline(w * tan_s * cos_s / w, color="C0", ls=":", label="W sin (static balance)")
        a.axhline(0.5 * cos_s, color="C1", ls=":", label="mu W cos (Coulomb limit)")
        a.set_ylim(0, 1.0)
        a.set_xlabel("t [s]")
        a.set_ylabel("contact force / buoyant weight")
        b = a.twinx()
        b.plot(d["t"], 1e3 * d["x"], color="C2", label="displacement [mm]")
        b.set_ylabel("displacement down the slope [mm]")
        a.set_title(f"slope tan = {ratio:.1f} mu: moved {1e3 * d['x'][-1]:.1f} mm, "
                    f"v(3 s) = {d['vx'][-1]:.1e} m/s", fontsize=10)
        h1, l1 = a.get_legend_handles_labels()
        h2, l2 = b.get_legend_handles_labels()
        a.legend(h1 + h2, l1 + l2, fontsize=7, loc="center right")

    fig.tight_layout()
    fig.savefig(os.path.join(HERE, "moving_bodies.png"), dpi=110)


if __name__ == "__main__":
    main(sys.argv[1] if len(sys.argv) > 1 else "bench/fem/runs")
