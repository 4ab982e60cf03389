#!/usr/bin/python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""Plots of the finite-volume fluid validation (tests/validation/test_fluid_fv_validation.cpp).

Usage: /usr/bin/python3 scripts/plot_fluid_fv.py [--out DIR] [BUILD_DIR]   (default build/release)

Runs gf_validation_tests --gtest_filter='FluidFVValidation*' with GF_VALIDATION_OUT set and
writes docs/validation/fluid_fv_cavity.png (centre-line profiles of the lid-driven cavity at
Re = 100 against Ghia, Ghia & Shin 1982) and docs/validation/fluid_fv_convergence.png (grid
convergence of plane Poiseuille flow and of the Taylor-Green vortex); with --out DIR, into DIR
(created if missing) instead. Uses Debian's python3-numpy and python3-matplotlib."""
import os

import numpy as np

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

import validation_run  # noqa: E402

# Ghia, Ghia & Shin, J. Comput. Phys. 48 (1982) 387, Re = 100: Table I (u on x = 0.5) and
# Table II (v on y = 0.5).
GHIA_Y = [1.0000, 0.9766, 0.9688, 0.9609, 0.9531, 0.8516, 0.7344, 0.6172, 0.5000, 0.4531,
          0.2813, 0.1719, 0.1016, 0.0703, 0.0625, 0.0547, 0.0000]
GHIA_U = [1.00000, 0.84123, 0.78871, 0.73722, 0.68717, 0.23151, 0.00332, -0.13641, -0.20581,
          -0.21090, -0.15662, -0.10150, -0.06434, -0.04775, -0.04192, -0.03717, 0.00000]
GHIA_X = [1.0000, 0.9688, 0.9609, 0.9531, 0.9453, 0.9063, 0.8594, 0.8047, 0.5000, 0.2344,
          0.2266, 0.1563, 0.0938, 0.0781, 0.0703, 0.0625, 0.0000]
GHIA_V = [0.00000, -0.05906, -0.07391, -0.08864, -0.10313, -0.16914, -0.22445, -0.24533,
          0.05454, 0.17527, 0.17507, 0.16077, 0.12317, 0.10890, 0.10091, 0.09233, 0.00000]


def load(folder, name):
    return np.genfromtxt(os.path.join(folder, name + ".csv"), delimiter=",", names=True)


def cavity(folder, out):
    fig, ax = plt.subplots(1, 2, figsize=(11, 4.6))
    for name, style in (("van_leer", "-"), ("central", "--")):
        d = load(folder, "fluid_fv_cavity_" + name)
        label = "grainflow 64 x 64, " + name.replace("_", " ")
        ax[0].plot(d["u_of_y"], d["s"], style, label=label)
        ax[1].plot(d["s"], d["v_of_x"], style, label=label)
    ax[0].plot(GHIA_U, GHIA_Y, "ko", mfc="none", label="Ghia et al. (1982), Table I")
    ax[1].plot(GHIA_X, GHIA_V, "ko", mfc="none", label="Ghia et al. (1982), Table II")
    ax[0].set_xlabel("u / U_lid on x = 0.5")
    ax[0].set_ylabel("y / L")
    ax[1].set_xlabel("x / L")
    ax[1].set_ylabel("v / U_lid on y = 0.5")
    for a in ax:
        a.grid(alpha=0.3)
        a.legend(fontsize=8)
    fig.suptitle("Lid-driven cavity, Re = 100 (tolerance: 2 % of U_lid at the 17 points)")
    fig.tight_layout()
    fig.savefig(os.path.join(out, "fluid_fv_cavity.png"), dpi=120)


def convergence(folder, out):
    fig, ax = plt.subplots(1, 2, figsize=(11, 4.4))
    p = load(folder, "fluid_fv_poiseuille_convergence")
    n = p["n"]
    ax[0].loglog(n, p["error"], "o-", label="grainflow: max |u - u_exact| / u_max")
    ax[0].loglog(n, 1.0 / n ** 2, "k:", label="discrete analysis: (h/H)^2")
    ax[0].set_xlabel("cells across the channel")
    ax[0].set_ylabel("max error / u_max")
    ax[0].set_title("Plane Poiseuille flow (body force)")
    t = load(folder, "fluid_fv_taylor_green_convergence")
    n = t["n"]
    ax[1].loglog(n, t["central"], "o-", label="central")
    ax[1].loglog(n, t["van_leer"], "s-", label="van Leer")
    if "upwind" in t.dtype.names:
        ax[1].loglog(n, t["upwind"], "^-", label="upwind")
        ax[1].loglog(n, t["upwind"][0] * (n[0] / n), "k--", label="slope 1")
    ax[1].loglog(n, t["central"][0] * (n[0] / n) ** 2, "k:", label="slope 2")
    ax[1].set_xlabel("cells per 2 pi")
    ax[1].set_ylabel("max |u - u_exact| at t = 1")
    ax[1].set_title("Taylor-Green vortex, nu = 0.05, dt = 1 / (2 N)")
    for a in ax:
        a.grid(alpha=0.3, which="both")
        a.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(os.path.join(out, "fluid_fv_convergence.png"), dpi=120)


def main():
    validation_run.plot_main(__doc__, "FluidFVValidation*", [cavity, convergence],
                             OMP_NUM_THREADS="1")


if __name__ == "__main__":
    main()
