#!/usr/bin/python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""Plot of the momentum-balance validation of wall-driven shear
(tests/validation/test_rheology_validation.cpp, RheologyValidation.SphereWallShearBalancesMomentum):
the layer's shear and normal stress against the shear walls' tractions over the run, for the
shipped sphere shear box (rough walls: friction 1, rolling resistance 0.5) and the same box with
smooth walls (friction 0.5, none), whose spheres roll and whose flow decays.

Usage: /usr/bin/python3 scripts/plot_momentum_balance.py [--out DIR] [BUILD_DIR]
(default build/release)

Runs gf_validation_tests --gtest_filter=RheologyValidation.SphereWallShearBalancesMomentum
(about 5 s on one core) with GF_VALIDATION_OUT set and writes
docs/validation/rheology_momentum_balance.png (into DIR, created if missing, with --out DIR):
means over strain windows of 2 of sigma_xz, sigma_zz (the layer, streaming + collisional) and
wall_sigma_xz, wall_sigma_zz (the walls' tractions), and the bulk shear rate. Uses Debian's
python3-numpy and python3-matplotlib."""
import os

import numpy as np

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

import validation_run  # noqa: E402

WINDOW = 2.0  # strain per plotted mean (40 samples of 0.05)
WALLS = {0: "rough walls (shipped)", 1: "smooth walls"}


def window_means(strain, values):
    """Means of values over consecutive strain windows of WINDOW; the windows' centres."""
    edges = np.arange(0.0, strain.max() + WINDOW, WINDOW)
    k = np.digitize(strain, edges) - 1
    centres, means = [], []
    for w in range(len(edges) - 1):
        m = k == w
        if m.any():
            centres.append(0.5 * (edges[w] + edges[w + 1]))
            means.append(values[m].mean())
    return np.array(centres), np.array(means)


def plot(folder, out):
    d = np.atleast_1d(np.genfromtxt(os.path.join(folder, "rheology_momentum_balance.csv"),
                                    delimiter=",", names=True))
    fig, ax = plt.subplots(1, 3, figsize=(14, 4.2))
    for kind, label in WALLS.items():
        r = d[d["walls"] == kind]
        colour = "C0" if kind == 0 else "C3"
        for a, layer, wall, name in [(ax[0], "sigma_xz", "wall_sigma_xz", "-sigma_xz"),
                                     (ax[1], "sigma_zz", "wall_sigma_zz", "sigma_zz")]:
            sign = -1.0 if layer == "sigma_xz" else 1.0
            x, m = window_means(r["strain"], sign * r[layer])
            a.plot(x, m, "o-", color=colour, ms=3, label=f"{label}: layer")
            x, m = window_means(r["strain"], sign * r[wall])
            a.plot(x, m, "s--", color=colour, ms=3, mfc="none", label=f"{label}: walls")
            a.set_ylabel(f"{name} (Pa)")
        x, m = window_means(r["strain"], r["shear_rate"])
        ax[2].plot(x, m, "o-", color=colour, ms=3, label=label)
    ax[0].set_title("Shear stress: layer against walls")
    ax[1].set_title("Normal stress: layer against walls")
    ax[2].axhline(100.0, color="k", lw=0.8, label="imposed (wall speeds)")
    ax[2].set_ylabel("bulk shear rate (1/s)")
    ax[2].set_title("Shear rate of the layer")
    for a in ax:
        a.set_xlabel(f"strain (means over windows of {WINDOW:g})")
        a.legend(fontsize=7)
    fig.suptitle("Spheres (phi = 0.1, e = 0.7) sheared between walls: momentum balance", fontsize=10)
    fig.tight_layout()
    fig.savefig(os.path.join(out, "rheology_momentum_balance.png"), dpi=120)
    plt.close(fig)


if __name__ == "__main__":
    validation_run.plot_main(__doc__, "RheologyValidation.SphereWallShearBalancesMomentum", [plot],
                             OMP_NUM_THREADS="1")
