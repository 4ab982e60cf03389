#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-3.0-or-later
# Runs the heat validation tests with curve output on and plots them against their closed forms
# and correlations: conduction through contacts (docs/models/heat.md) and grain-fluid heat
# transfer in CFD-DEM (docs/models/cfd_dem.md).
"""Usage: /usr/bin/python3 docs/validation/make_heat_plots.py [--out DIR] [BUILD_DIR]
(BUILD_DIR default build/release)

Writes docs/validation/dem_heat.png, cfd_dem_heat.png and cfd_dem_natural_convection.png (or
into DIR). Uses Debian's python3-numpy and
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


def plot_fluid(folder, out):
    fig, axes = plt.subplots(2, 2, figsize=(11, 8.4))
    ax = axes[0]
    for law, marker in (("ranz_marshall", "o"), ("gunn", "s")):
        w = load(os.path.join(folder, f"cfd_dem_heat_bead_water_{law}.csv"))
        ax[0].plot(w["t"], w["temperature"], marker, mfc="none", ms=4, markevery=4,
                   label=f"grainflow, {law}")
    ax[0].plot(w["t"], w["exact"], "k-", lw=0.8, label="300 K + 100 K exp(-t / tau), Nu = 2")
    ax[0].set_xlabel("time (s)")
    ax[0].set_ylabel("bead temperature (K)")
    ax[0].set_title("glass bead (d = 2 mm) at 400 K in still water at 300 K", fontsize=9)
    ax[0].legend(fontsize=8)

    a = load(os.path.join(folder, "cfd_dem_heat_bead_air.csv"))
    re = np.logspace(0, 3.2, 100)
    pr = 1005 * 1.8e-5 / 0.026
    ax[1].plot(re, 2 + 0.6 * np.sqrt(re) * np.cbrt(pr), "k-", lw=0.8,
               label="Ranz-Marshall 2 + 0.6 Re^1/2 Pr^1/3")
    eps = 1.0
    gunn = ((7 - 10 * eps + 5 * eps**2) * (1 + 0.7 * re**0.2 * np.cbrt(pr))
            + (1.33 - 2.4 * eps + 1.2 * eps**2) * re**0.7 * np.cbrt(pr))
    ax[1].plot(re, gunn, "k--", lw=0.8, label="Gunn (1978), eps = 1")
    for code, law, marker in ((0, "ranz_marshall", "o"), (1, "gunn", "s")):
        sel = np.isclose(a["law"], code)
        ax[1].loglog(a["re"][sel], a["nu"][sel], marker, mfc="none",
                     label=f"grainflow, {law}: from the bead's cooling rate")
    ax[1].set_xlabel("Re = rho_f |u_f - v| d / mu")
    ax[1].set_ylabel("Nu")
    ax[1].set_title("the bead in an air stream (Pr = 0.70)", fontsize=9)
    ax[1].legend(fontsize=8)

    # The fluid's temperature alone: van Leer's face values against upwinding.
    ax = axes[1]
    p = load(os.path.join(folder, "cfd_dem_heat_pulse.csv"))
    sel = np.isclose(p["courant"], 0.1)
    x = p["x"][sel] * 1e3
    ax[0].plot(x, p["initial"][sel], "k-", lw=0.8, label="exact (the initial profile)")
    ax[0].plot(x, p["van_leer"][sel], "o", mfc="none", ms=4, label="van_leer (default)")
    ax[0].plot(x, p["upwind"][sel], "s", mfc="none", ms=4, label="upwind")
    ax[0].set_xlabel("x (mm)")
    ax[0].set_ylabel("fluid temperature (K)")
    ax[0].set_title("a pulse carried once around a periodic box, 40 cells, Courant 0.1",
                    fontsize=9)
    ax[0].legend(fontsize=8)

    c = load(os.path.join(folder, "cfd_dem_heat_channel_convergence.csv"))
    ax[1].loglog(c["cells"], c["van_leer_interior"], "o-", mfc="none",
                 label="van_leer, all cells but the last three")
    ax[1].loglog(c["cells"], c["van_leer_outlet"], "^-", mfc="none",
                 label="van_leer, the last three (zero-gradient outlet)")
    ax[1].loglog(c["cells"], c["upwind"], "s-", mfc="none", label="upwind")
    n = c["cells"]
    ax[1].loglog(n, c["upwind"][0] * (n[0] / n), "k:", lw=0.8, label="slope -1")
    ax[1].loglog(n, c["van_leer_interior"][0] * (n[0] / n) ** 2, "k--", lw=0.8,
                 label="slope -2")
    ax[1].set_xlabel("cells along the channel")
    ax[1].set_ylabel("max |T - T_exact| at the cell centres (K)")
    ax[1].set_title("steady channel through a heat-exchanging bed (exponential profile)",
                    fontsize=9)
    ax[1].legend(fontsize=8)
    fig.suptitle("grain-fluid heat transfer in CFD-DEM (docs/models/cfd_dem.md)")
    fig.tight_layout()
    fig.savefig(os.path.join(out, "cfd_dem_heat.png"), dpi=120)
    plot_cavity(folder, out)


def plot_cavity(folder, out):
    c = load(os.path.join(folder, "cfd_dem_heat_cavity.csv"))
    ref_ra = np.array([1e3, 1e4, 1e5])
    ref_nu = np.array([1.1178, 2.24475, 4.52164])  # Hortmann, Peric & Scheuerer (1990)
    ref_u = np.array([3.649, 16.178, 34.73])  # de Vahl Davis (1983), u_max and v_max
    ref_v = np.array([3.697, 19.617, 68.59])
    fig, ax = plt.subplots(1, 2, figsize=(11, 4.2))
    ax[0].loglog(ref_ra, ref_nu, "k*", ms=10, label="mesh-converged (Hortmann et al. 1990)")
    for n, marker in ((20, "s"), (40, "o")):
        sel = np.isclose(c["cells"], n)
        ax[0].loglog(c["ra"][sel], c["nu"][sel], marker, mfc="none", label=f"grainflow, {n} x {n} cells")
    ax[0].set_xlabel("Ra = g beta dT L^3 / (nu alpha)")
    ax[0].set_ylabel("Nu of the hot wall")
    ax[0].set_title("differentially heated square cavity, Pr = 0.71", fontsize=9)
    ax[0].legend(fontsize=8)
    sel = np.isclose(c["cells"], 40)
    ax[1].loglog(ref_ra, ref_u, "k*", ms=10, label="de Vahl Davis (1983): u_max, v_max")
    ax[1].loglog(ref_ra, ref_v, "k*", ms=10)
    ax[1].loglog(c["ra"][sel], c["u_max"][sel], "o", mfc="none",
                 label="grainflow, 40 x 40: u_max on the vertical mid-line")
    ax[1].loglog(c["ra"][sel], c["v_max"][sel], "s", mfc="none",
                 label="grainflow, 40 x 40: v_max on the horizontal mid-line")
    ax[1].set_xlabel("Ra")
    ax[1].set_ylabel("velocity maximum (alpha / L)")
    ax[1].legend(fontsize=8)
    fig.suptitle("Boussinesq buoyancy of the CFD-DEM fluid (fluid.thermal_expansion)")
    fig.tight_layout()
    fig.savefig(os.path.join(out, "cfd_dem_natural_convection.png"), dpi=120)


if __name__ == "__main__":
    validation_run.plot_main(__doc__, "ValidationHeat.*:CfdDemHeatValidation.*",
                             [plot, plot_fluid])
