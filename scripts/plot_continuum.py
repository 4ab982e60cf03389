#!/usr/bin/python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""Plots of the continuum (SPH) validation (tests/validation/test_sph_validation.cpp).

Usage: /usr/bin/python3 scripts/plot_continuum.py [--out DIR] [BUILD_DIR]   (default build/release)

Runs gf_validation_tests --gtest_filter='ValidationSph*' (about 40 s) with GF_VALIDATION_OUT set
and writes docs/validation/continuum_sph.png (into DIR, created if missing, with --out DIR):
transient plane Poiseuille flow against its series solution, the pressure of a liquid at rest
against rho g depth, the Bagnold profile of a mu(I) layer on an incline, and a mu(I) layer below
its yield slope against the creeping film of the regularisation, a Poiseuille flow against a
free-slip plate, and Taylor-Couette flow between a turning and a fixed cylinder. Uses Debian's
python3-numpy and python3-matplotlib."""
import os

import numpy as np

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

import validation_run  # noqa: E402


def load(folder, name):
    return np.genfromtxt(os.path.join(folder, name + ".csv"), delimiter=",", names=True)


def finish(a, xlabel, ylabel, title):
    a.set_xlabel(xlabel)
    a.set_ylabel(ylabel)
    a.set_title(title, fontsize=9)
    a.legend(fontsize=7)


def main():
    args = validation_run.parser(__doc__).parse_args()
    os.makedirs(args.out, exist_ok=True)
    with validation_run.validation_run(args.build, "ValidationSph*", OMP_NUM_THREADS="2") as f:
        pois = load(f, "sph_poiseuille")
        hyd = load(f, "sph_hydrostatic")
        bag = load(f, "sph_bagnold")
        creep = load(f, "sph_creep_1000")
        slip = load(f, "sph_poiseuille_free_slip")
        tc = load(f, "sph_taylor_couette_20")
    fig, axes = plt.subplots(2, 3, figsize=(16, 8.6))
    ax = axes.ravel()
    a = ax[0]
    for t in np.unique(pois["t"]):
        d = pois[pois["t"] == t]
        o = np.argsort(d["y"])
        a.plot(d["u"][o] * 1e5, d["y"][o] * 1e3, "o", ms=3, label=f"t = {t:g} s")
        a.plot(d["u_exact"][o] * 1e5, d["y"][o] * 1e3, "k-", lw=0.7)
    finish(a, "u (1e-5 m/s)", "y (mm)",
           "Poiseuille flow from rest (Morris et al. 1997)\nlines: series solution")
    a = ax[1]
    a.plot(hyd["p"], hyd["y"], ".", ms=3, label="grainflow SPH, t = 1 s")
    a.plot(hyd["p_exact"][np.argsort(hyd["y"])], np.sort(hyd["y"]), "k-", lw=0.8,
           label="rho g depth")
    finish(a, "p (Pa)", "y (m)", "Water at rest in a tank (20 particles deep)")
    a = ax[2]
    a.plot(bag["u"], bag["y"] * 1e3, "o", ms=4, label="grainflow SPH, mu(I), t = 4 s")
    a.plot(bag["u_exact"], bag["y"] * 1e3, "k-", lw=0.8, label="Bagnold profile")
    err = np.max(np.abs(bag["u"] - bag["u_exact"])) / bag["u_exact"].max()
    finish(a, "u (m/s)", "y (mm)",
           f"mu(I) layer on a 25 deg incline (max error {100 * err:.1f} % of u_s)")
    a = ax[3]
    a.plot(creep["u"] * 1e3, creep["y"] * 1e3, "o", ms=4, label="grainflow SPH, implicit viscosity")
    a.plot(creep["u_exact"] * 1e3, creep["y"] * 1e3, "k-", lw=0.8,
           label="film of viscosity eta_max")
    finish(a, "u (mm/s)", "y (mm)", "mu(I) below yield, 15 deg, eta_max = 1e3 Pa s")
    a = ax[4]
    d = slip[slip["t"] == slip["t"].max()]
    o = np.argsort(d["y"])
    a.plot(d["u"][o] * 1e5, d["y"][o] * 1e3, "o", ms=3, label="grainflow SPH, t = %g s" % d["t"][0])
    a.plot(d["u_exact"][o] * 1e5, d["y"][o] * 1e3, "k-", lw=0.8,
           label="half of the flow between plates 2L apart")
    finish(a, "u (1e-5 m/s)", "y (mm)",
           "Poiseuille flow, no-slip bottom, free-slip top (slip: free_slip)")
    a = ax[5]
    o = np.argsort(tc["r"])
    a.plot(tc["r"][o] * 1e3, tc["u_theta"][o] * 1e3, "o", ms=4,
           label="grainflow SPH, ring means over t = 0.6-1 s")
    a.plot(tc["r"][o] * 1e3, tc["u_exact"][o] * 1e3, "k-", lw=0.8, label="A r + B / r")
    finish(a, "r (mm)", "u_theta (mm/s)",
           "Taylor-Couette: inner cylinder turning (Re = 1), 20 across")
    fig.tight_layout()
    path = os.path.join(args.out, "continuum_sph.png")
    fig.savefig(path, dpi=110)
    print(path)


if __name__ == "__main__":
    main()
