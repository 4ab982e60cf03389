#!/usr/bin/python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""Plots of the continuum (SPH) validation (tests/validation/test_sph_validation.cpp).

Usage: /usr/bin/python3 scripts/plot_continuum.py [--out DIR] [BUILD_DIR]   (default build/release)

Runs gf_validation_tests --gtest_filter='ValidationSph*' (about 90 s) with GF_VALIDATION_OUT set
and writes docs/validation/continuum_sph.png (into DIR, created if missing, with --out DIR):
transient plane Poiseuille flow against its series solution, the pressure of a liquid at rest
against rho g depth, the Bagnold profile of a mu(I) layer on an incline, and a mu(I) layer below
its yield slope against the creeping film of the regularisation, a Poiseuille flow against a
free-slip plate, Taylor-Couette flow between a turning and a fixed cylinder, Poiseuille and
Couette flows between Navier-slip plates, and the kinetic-theory mode: a granular gas cooling
(Haff's law) and a granular gas sheared between plates reaching the theory's homogeneous shear
state. Uses Debian's python3-numpy and python3-matplotlib."""
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
        navier = [load(f, "sph_navier_slip_f1_u0"), load(f, "sph_navier_slip_f0_u1")]
        haff = load(f, "sph_ktgf_haff")
        kt = load(f, "sph_ktgf_couette")
    fig, axes = plt.subplots(3, 3, figsize=(16, 12.6))
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
    a = ax[6]
    for d, lab in zip(navier, ["Poiseuille, bottom b = L/4", "Couette, both b = L/4"]):
        o = np.argsort(d["y"])
        scale = np.abs(d["u_exact"]).max()
        a.plot(d["u"][o] / scale, d["y"][o] * 1e3, "o", ms=3, label=f"grainflow SPH, {lab}")
        a.plot(d["u_exact"][o] / scale, d["y"][o] * 1e3, "k-", lw=0.8)
    a.axvline(0, color="0.6", lw=0.5)
    finish(a, "u / largest speed", "y (mm)",
           "Navier slip u - u_w = b du/dn (slip: {slip_length: b})\nlines: exact, steady")
    a = ax[7]
    a.plot(haff["t"], haff["theta"], "o", ms=3, label="grainflow SPH, kinetic theory")
    a.plot(haff["t"], haff["theta_haff"], "k-", lw=0.8, label="Haff: Theta0 / (1 + t/tau)^2")
    finish(a, "t (s)", "Theta (m^2/s^2)", "Granular gas cooling at rest (a = 0.1, e = 0.7)")
    a = ax[8]
    for q, ex, lab in (("theta", "theta_exact", "Theta"), ("pressure", "p_exact", "P (plates)"),
                       ("shear_stress", "tau_exact", "shear stress (plates)")):
        a.plot(kt["t"], kt[q] / kt[ex], "-", label=lab)
    a.axhline(1.0, color="k", lw=0.8)
    a.axhspan(0.95, 1.05, color="0.9", label="+- 5 %")
    a.set_ylim(0, 1.2)
    finish(a, "t (s)", "SPH / kinetic theory (lun, a = 0.1)",
           "Granular gas sheared between plates (e = 0.95, 100 1/s), from rest and cold")
    fig.tight_layout()
    path = os.path.join(args.out, "continuum_sph.png")
    fig.savefig(path, dpi=110)
    print(path)


if __name__ == "__main__":
    main()
