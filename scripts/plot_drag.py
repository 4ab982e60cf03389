#!/usr/bin/python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""Plots of the CFD-DEM drag-law validation (tests/validation/test_drag_validation.cpp).

Usage: /usr/bin/python3 scripts/plot_drag.py [--out DIR] [BUILD_DIR]   (default build/release)

Runs gf_validation_tests --gtest_filter='DragValidation*' with GF_VALIDATION_OUT set and writes
docs/validation/drag_terminal.png, drag_laws.png and drag_hs_rod.png (into DIR, created if
missing, with --out DIR). Uses Debian's python3-numpy and python3-matplotlib."""
import os

import numpy as np

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

import validation_run  # noqa: E402

LAWS = ["schiller_naumann", "di_felice", "wen_yu", "gidaspow", "beetstra", "holzer_sommerfeld"]
STYLE = {"schiller_naumann": "-", "di_felice": "--", "wen_yu": ":", "gidaspow": "-.",
         "beetstra": "-", "holzer_sommerfeld": "--"}


def load(folder, name):
    return np.genfromtxt(os.path.join(folder, name + ".csv"), delimiter=",", names=True)


def terminal(folder, out):
    fig, ax = plt.subplots(1, 2, figsize=(11, 4.2))
    # Gas case of the issue: d = 100 um, rho_p = 3000, rho_f = 10, nu = 1e-5.
    a = ax[0]
    for law in LAWS:
        d = load(folder, "drag_terminal_gas_" + law)
        a.plot(d["t"] * 1e3, d["v"], STYLE[law], label=law)
    a.axhline(0.13734, color="k", lw=0.8)
    a.axhspan(0.13734 * 0.99, 0.13734 * 1.01, color="0.85", label="0.13734 m/s +- 1 %")
    a.set_xlabel("t (ms)")
    a.set_ylabel("settling speed (m/s)")
    a.set_xlim(0, 150)
    a.set_title("d = 100 um, rho_p = 3000, rho_f = 10 kg/m3, nu = 1e-5 m2/s")
    a.legend(fontsize=7)
    # Stokes case: d = 10 um glass in water; against v_St (1 - exp(-t/tau)).
    a = ax[1]
    d_p, rho_p, rho_f, mu, g = 10e-6, 2500.0, 1000.0, 1e-3, 9.81
    v_st = (rho_p - rho_f) * g * d_p ** 2 / (18 * mu)
    tau = rho_p * d_p ** 2 / (18 * mu)
    for law in LAWS:
        d = load(folder, "drag_terminal_stokes_" + law)
        a.plot(d["t"] / tau, d["v"] / v_st, STYLE[law], label=law)
    t = np.linspace(0, 10, 400)
    a.plot(t, 1 - np.exp(-t), "k:", lw=1.5, label="Stokes: 1 - exp(-t/tau)")
    a.axhspan(0.99, 1.01, color="0.85", label="+- 1 %")
    a.set_xlabel("t / tau,  tau = rho_p d^2 / (18 mu)")
    a.set_ylabel("v / v_Stokes")
    a.set_xlim(0, 10)
    a.set_title("Stokes regime: d = 10 um, glass in water (Re = 8e-4)")
    a.legend(fontsize=7)
    fig.suptitle("Terminal settling of one sphere (gravity, buoyancy -V grad p, drag; no added mass)")
    fig.tight_layout()
    fig.savefig(os.path.join(out, "drag_terminal.png"), dpi=120)


def laws(folder, out):
    fig, ax = plt.subplots(1, 3, figsize=(14, 4.2))
    a = ax[0]
    for law in LAWS:
        d = load(folder, "drag_curve_re_" + law)
        a.loglog(d["re"], d["f"], STYLE[law], label=law)
    a.set_xlabel("Re = rho |u| d / mu (eps = 1)")
    a.set_ylabel("f = F / (3 pi mu d |u|)")
    a.set_title("Single sphere")
    a.legend(fontsize=7)
    for k, re in enumerate((1, 100)):
        a = ax[k + 1]
        for law in LAWS:
            d = load(folder, "drag_curve_eps_re%d_%s" % (re, law))
            a.semilogy(d["eps"], d["f"], STYLE[law], label=law)
        a.axvline(0.8, color="0.6", lw=0.6)
        a.set_xlabel("fluid fraction eps (gidaspow switches at 0.8)")
        a.set_ylabel("f = F / (3 pi mu d |u|),  |u| interstitial")
        a.set_title("Re_e = eps rho |u| d / mu = %d" % re)
        a.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(os.path.join(out, "drag_laws.png"), dpi=120)


def hs_rod(folder, out):
    d = load(folder, "drag_hs_rod")
    re = d["re"]
    sn = np.where(re < 1000, 24 / re * (1 + 0.15 * re ** 0.687), 0.44)
    fig, ax = plt.subplots(figsize=(6.5, 4.5))
    ax.loglog(re, d["cd_end_on"], label="spherocylinder L/d = 4, flow along the axis")
    ax.loglog(re, d["cd_broadside"], label="spherocylinder L/d = 4, broadside")
    ax.loglog(re, d["cd_sphere"], "--", label="sphere (holzer_sommerfeld)")
    ax.loglog(re, sn, "k:", label="sphere (schiller_naumann)")
    ax.set_xlabel("Re = rho |u| d_v / mu")
    ax.set_ylabel("C_D (reference area pi d_v^2 / 4)")
    ax.set_title("Hoelzer & Sommerfeld (2008)")
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(os.path.join(out, "drag_hs_rod.png"), dpi=120)


def main():
    validation_run.plot_main(__doc__, "DragValidation*", [terminal, laws, hs_rod])


if __name__ == "__main__":
    main()
