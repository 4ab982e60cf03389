#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-3.0-or-later
# Runs the heat conduction validation tests with curve output on and plots them against their
# closed forms (docs/models/heat.md).
"""Usage: /usr/bin/python3 docs/validation/make_heat_plots.py [--out DIR] [BUILD_DIR]
(BUILD_DIR default build/release)

Writes docs/validation/dem_heat.png (or into DIR). Uses Debian's python3-numpy and
python3-matplotlib."""
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

HERE = os.path.dirname(os.path.realpath(__file__))
sys.path.insert(0, os.path.normpath(os.path.join(HERE, os.pardir, os.pardir, "scripts")))
import validation_run  # noqa: E402


def load(path):
    return np.genfromtxt(path, delimiter=",", names=True)


def plot(folder, out):
    fig, ax = plt.subplots(1, 2, figsize=(11, 4.2))
    c = load(os.path.join(folder, "heat_chain.csv"))
    for factor, name, marker in ((1.0, "batchelor_obrien", "o"),
                                 (np.sqrt(2 * np.pi), "intersection_area", "s")):
        sel = np.isclose(c["model"], factor)
        order = np.argsort(c["k"][sel])
        z = c["z"][sel][order] * 1e3
        ax[0].plot(z, c["analytic"][sel][order], "k-", lw=0.8)
        ax[0].plot(z, c["temperature"][sel][order], marker, mfc="none", label=f"grainflow, {name}")
    ax[0].plot([], [], "k-", lw=0.8, label="series conductances of the Hertz contacts")
    ax[0].set_xlabel("height of the sphere's centre (mm)")
    ax[0].set_ylabel("steady temperature (K)")
    ax[0].set_title("six spheres pressed (0.01 N) between a floor at 400 K and a lid at 300 K",
                    fontsize=9)
    ax[0].legend(fontsize=8)

    t = load(os.path.join(folder, "heat_two_spheres.csv"))
    ax[1].semilogy(t["t"] * 1e3, t["difference"], "-", label="grainflow (explicit steps)")
    ax[1].semilogy(t["t"] * 1e3, t["exponential"], "k--", lw=0.8,
                   label="100 K exp(-2 H t / (m c))")
    ax[1].set_xlabel("time (ms)")
    ax[1].set_ylabel("T_1 - T_2 (K)")
    ax[1].set_title("two spheres between adiabatic walls", fontsize=9)
    ax[1].legend(fontsize=8)
    fig.suptitle("heat conduction through contacts (docs/models/heat.md)")
    fig.tight_layout()
    fig.savefig(os.path.join(out, "dem_heat.png"), dpi=120)


if __name__ == "__main__":
    validation_run.plot_main(__doc__, "ValidationHeat.*", [plot])
