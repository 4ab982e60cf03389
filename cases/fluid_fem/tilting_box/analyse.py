#!/usr/bin/python3
# SPDX-License-Identifier: GPL-3.0-or-later
# The tilting-box test of cases/fluid_fem/tilting_box:
#   grainflow run cases/fluid_fem/tilting_box/case.yaml --output out/tilting_box
#   /usr/bin/python3 cases/fluid_fem/tilting_box/analyse.py out/tilting_box
# prints, over time, the box's tilt theta, the bed surface's angle to the horizontal and the
# grains' mean speed; the avalanches (peaks of the mean speed while tilting), the largest surface
# angle while tilting (the maximum angle of stability) and the angle kept in the last second
# (the angle of repose); draws docs/validation/fem/tilting_box.png.
#
# Surface: the highest grain point in vertical strips of the box one mean grain diameter wide,
# the strips at the side walls left out, fitted by a straight line in the box's frame (angle
# alpha, negative when the surface falls towards +x); seen from the horizontal the surface
# slopes by beta = theta + alpha (the box turns counter-clockwise by theta, its +x side up).
import os
import re
import sys

import matplotlib
import numpy as np

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(os.path.dirname(HERE)))
sys.path.insert(0, os.path.join(HERE, "..", "polygons_sedimenting"))
from analyse import outline, polygons  # noqa: E402


def main(out_dir, case):
    text = open(case).read()
    rate, t0, t1 = (float(v) for v in re.search(
        r"tilt:\s*\{rate:\s*([-+0-9.eE]+),\s*start:\s*([-+0-9.eE]+),\s*end:\s*([-+0-9.eE]+)\}",
        text).groups())
    width = float(re.search(r"outline:\s*\[\[0, 0\], \[([0-9.eE+-]+), 0\]", text).group(1))
    shapes = polygons(case)
    names = sorted(shapes)
    with open(os.path.join(out_dir, "fem_forces.csv")) as f:
        cols = {c: i for i, c in enumerate(f.readline().strip().split(","))}
    data = np.loadtxt(os.path.join(out_dir, "fem_forces.csv"), delimiter=",", skiprows=1)
    t = data[:, cols["t"]]
    theta = rate * (np.clip(t, t0, t1) - t0)
    d = 2 * np.sqrt(np.mean([s[2] for s in shapes.values()]) / np.pi)
    speed = np.hypot(data[:, [cols[n + ".vx"] for n in names]],
                     data[:, [cols[n + ".vy"] for n in names]]).mean(axis=1)

    def surface(i):
        pts = np.vstack([outline(shapes[n], data[i], cols, n) for n in names])
        edges = np.linspace(0, width, int(round(width / d)) + 1)
        sx, sh = [], []
        for lo, hi in zip(edges[1:-2], edges[2:-1]):  # (the strips at the walls left out)
            sel = (pts[:, 0] >= lo) & (pts[:, 0] < hi)
            if sel.any():
                sx.append(0.5 * (lo + hi))
                sh.append(pts[sel, 1].max())
        fit = np.polyfit(sx, sh, 1)
        return np.degrees(np.arctan(fit[0])), np.array(sx), np.array(sh), fit, pts

    every = max(1, len(t) // 400)
    idx = np.arange(0, len(t), every)
    alpha = np.array([surface(i)[0] for i in idx])
    beta = theta[idx] + alpha
    tilting = (t[idx] > t0) & (t[idx] <= t1)
    k_max = np.flatnonzero(tilting)[np.argmax(beta[tilting])]
    i_max, beta_max = idx[k_max], beta[k_max]
    # avalanches: local peaks of the grains' mean speed while tilting, above twice its median
    # then and at least 0.5 s apart
    sp = speed[idx]
    floor = 2 * np.median(sp[tilting])
    peaks = []
    for k in np.flatnonzero(tilting)[1:-1]:
        if sp[k] > floor and sp[k] >= sp[k - 1] and sp[k] >= sp[k + 1]:
            if peaks and t[idx[k]] - t[idx[peaks[-1]]] < 0.5:
                if sp[k] > sp[peaks[-1]]:
                    peaks[-1] = k
            else:
                peaks.append(k)
    last = t[idx] >= t[-1] - 1.0
    repose = beta[last].mean()
    print(f"grains {len(names)}, mean diameter of equal area {1e3 * d:.2f} mm, tilt {rate:g} deg/s "
          f"from {t0:g} s to {t1:g} s")
    for k in range(0, len(idx), max(1, len(idx) // 25)):
        i = idx[k]
        print(f"  t = {t[i]:6.2f} s  tilt {theta[i]:5.1f} deg  surface {beta[k]:5.1f} deg to the "
              f"horizontal  mean speed {1e3 * speed[i]:6.2f} mm/s")
    print("avalanches (mean grain speed peaks above twice its median while tilting): " +
          ", ".join(f"tilt {theta[idx[k]]:.1f} deg ({1e3 * sp[k]:.2f} mm/s)" for k in peaks))
    print(f"maximum angle of stability (largest surface angle while tilting): {beta_max:.1f} deg "
          f"at tilt {theta[i_max]:.1f} deg")
    print(f"angle of repose (surface to the horizontal, mean of the last second): {repose:.1f} deg")
    print(f"grains' mean speed at the end {1e3 * speed[-1]:.3f} mm/s")

    fig, ax = plt.subplots(1, 2, figsize=(11, 4.6))
    a = ax[0]
    for k, (i, label) in enumerate(((idx[np.searchsorted(t[idx], t0)], "bed before the tilt"),
                                    (i_max, "steepest"), (len(t) - 1, "end"))):
        th = np.radians(theta[i])
        rot = np.array([[np.cos(th), -np.sin(th)], [np.sin(th), np.cos(th)]])
        box = np.array([[0, 0], [width, 0], [width, 0.045], [0, 0.045], [0, 0]]) @ rot.T
        a.plot(1e3 * box[:, 0], 1e3 * box[:, 1], color=f"C{k}", lw=1)
        for j, n in enumerate(names):
            v = outline(shapes[n], data[i], cols, n) @ rot.T
            a.fill(1e3 * v[:, 0], 1e3 * v[:, 1], color=f"C{k}", alpha=0.35,
                   label=f"{label}, t = {t[i]:.1f} s" if j == 0 else None)
    a.set_aspect("equal")
    a.set_xlabel("x [mm] (horizontal)")
    a.set_ylabel("y [mm]")
    a.set_title(f"{len(names)} polygons in a tilting box (mu = 0.5 on the film)")
    a.legend(fontsize=7, loc="upper left")
    a = ax[1]
    a.plot(t[idx], theta[idx], "k--", label="tilt of the box")
    a.plot(t[idx], beta, "C0", label="bed surface to the horizontal")
    a.axhline(repose, color="C0", ls=":", label=f"angle of repose {repose:.1f} deg")
    a.axhline(np.degrees(np.arctan(0.5)), color="C3", ls=":", label="friction angle atan 0.5")
    a.set_xlabel("t [s]")
    a.set_ylabel("angle [deg]")
    b = a.twinx()
    b.plot(t, 1e3 * speed, "C1", lw=0.8, label="mean grain speed")
    b.set_ylabel("mean grain speed [mm/s]", color="C1")
    a.legend(fontsize=7, loc="upper left")
    a.set_title("tilt, surface angle and avalanche")
    fig.tight_layout()
    fig.savefig(os.path.join(ROOT, "docs", "validation", "fem", "tilting_box.png"), dpi=110)


if __name__ == "__main__":
    main(sys.argv[1] if len(sys.argv) > 1 else "out/tilting_box",
         sys.argv[2] if len(sys.argv) > 2 else os.path.join(HERE, "case.yaml"))
