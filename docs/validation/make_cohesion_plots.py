#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-3.0-or-later
# Runs the sjkr cohesion validation tests with curve output on and plots them against the analytic
# equilibrium (docs/models/cohesion.md).
"""Usage: /usr/bin/python3 docs/validation/make_cohesion_plots.py [--out DIR] [BUILD_DIR]
(BUILD_DIR default build/release)

Writes docs/validation/dem_cohesion.png (or into DIR). Uses Debian's python3-numpy and
python3-matplotlib."""
import math
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

HERE = os.path.dirname(os.path.realpath(__file__))
sys.path.insert(0, os.path.normpath(os.path.join(HERE, os.pardir, os.pardir, "scripts")))
import validation_run  # noqa: E402

# The test's sphere and material (tests/validation/test_cohesion_validation.cpp).
R, E, NU = 1e-3, 1e7, 0.3
E_STAR = E / (2 * (1 - NU * NU))


def load(path):
    return np.genfromtxt(path, delimiter=",", names=True)


def hertz_equilibrium(kc):
    """Overlap where 4/3 E* sqrt(R) d^1.5 = kc pi d (2R - d): sqrt(d) solves a quadratic,
    4/3 E* sqrt(R) s = kc pi (2R - s^2)."""
    a, b, c = kc * math.pi, 4.0 / 3.0 * E_STAR * math.sqrt(R), -2 * R * kc * math.pi
    s = (-b + math.sqrt(b * b - 4 * a * c)) / (2 * a)
    return s * s


def plot(folder, out):
    fig, ax = plt.subplots(1, 3, figsize=(15, 4.2))
    f = load(os.path.join(folder, "cohesion_force.csv"))
    d = f["overlap"] * 1e6
    ax[0].plot(d, f["hertz"] * 1e3, "-", label="hertz_mindlin + sjkr (grainflow law)")
    ax[0].plot(d, f["hooke"] * 1e3, "-", label="hooke (k = 100 N/m) + sjkr")
    ax[0].plot(d, -f["cohesion"] * 1e3, "k--", lw=0.8, label="-k_c pi d (2R - d)")
    ax[0].axhline(0, color="0.6", lw=0.5)
    ax[0].set_xlabel("overlap (um)")
    ax[0].set_ylabel("normal force on the sphere (mN)")
    ax[0].set_title("sphere R = 1 mm on a wall, k_c = 1e5 J/m^3", fontsize=9)
    ax[0].legend(fontsize=8)

    s = load(os.path.join(folder, "cohesion_settled.csv"))
    wall = s[s["wall"] == 1]
    pair = s[s["wall"] == 0]
    kc = np.logspace(3.8, 5.8, 100)
    ax[1].loglog(kc, [hertz_equilibrium(k) * 1e6 for k in kc], "k-", lw=0.8,
                 label="analytic: 4/3 E* sqrt(R) d^1.5 = k_c A")
    ax[1].loglog(wall["kc"], wall["overlap"] * 1e6, "o", label="settled (sphere on wall)")
    ax[1].loglog(pair["kc"], pair["overlap"] * 1e6, "s", label="settled (two spheres)")
    ax[1].loglog(pair["kc"], pair["analytic"] * 1e6, "+", ms=12, color="k",
                 label="analytic (two spheres, bisection)")
    ax[1].set_xlabel("cohesion energy density k_c (J/m^3)")
    ax[1].set_ylabel("equilibrium overlap (um)")
    ax[1].set_title("hertz_mindlin, e = 0.3, no gravity", fontsize=9)
    ax[1].legend(fontsize=8)

    t = load(os.path.join(folder, "cohesion_approach.csv"))
    eq = hertz_equilibrium(1e5)
    ax[2].plot(t["t"] * 1e3, t["overlap"] * 1e6, "-", label="grainflow")
    ax[2].axhline(eq * 1e6, color="k", ls="--", lw=0.8, label="analytic equilibrium")
    ax[2].set_xlabel("time (ms)")
    ax[2].set_ylabel("overlap (um)")
    ax[2].set_title("approach at 20 um/s, k_c = 1e5 J/m^3 (wall)", fontsize=9)
    ax[2].legend(fontsize=8)
    fig.suptitle("sjkr cohesion: force law and settled overlap (docs/models/cohesion.md)")
    fig.tight_layout()
    fig.savefig(os.path.join(out, "dem_cohesion.png"), dpi=120)


if __name__ == "__main__":
    validation_run.plot_main(__doc__, "ValidationCohesion.*", [plot])
