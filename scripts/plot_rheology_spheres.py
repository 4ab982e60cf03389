#!/usr/bin/python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""Plot of the sphere rheology validation (tests/validation/test_rheology_validation.cpp):
homogeneous shear of dilute spheres (phi = 0.1, Lees-Edwards) against kinetic theory.

Usage: /usr/bin/python3 scripts/plot_rheology_spheres.py [--out DIR] [BUILD_DIR]
(default build/release)

Runs gf_validation_tests --gtest_filter='RheologyValidation.LeesEdwards*:RheologyValidation.
Dilute*:RheologyValidation.HomogeneousCooling*' (about 50 s on one core) with GF_VALIDATION_OUT
set and writes docs/validation/rheology_spheres_kinetic_theory.png (into DIR, created if
missing, with --out DIR): measured over predicted T, P and sigma_xz (Lun et al. 1984) at
e = 0.95 and e = 0.7, the coordination number over the Enskog collision frequency times the
contact duration, and the homogeneous cooling of a granular gas against Haff's law.
Uses Debian's python3-numpy and python3-matplotlib."""
import os

import numpy as np

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

import validation_run  # noqa: E402

QUANTITIES = ["T", "P", "-sigma_xz"]


def load(folder, name):
    return np.atleast_1d(np.genfromtxt(os.path.join(folder, name + ".csv"), delimiter=",",
                                       names=True))


def plot(folder, out):
    e095 = load(folder, "rheology_lees_edwards_e095")
    e07 = load(folder, "rheology_lees_edwards_e07")
    fig, ax = plt.subplots(1, 3, figsize=(16, 4.2))

    # Left: measured / Lun et al. per quantity; e = 0.95 (one run at 100 1/s), e = 0.7 (two rates).
    a = ax[0]
    x = np.arange(len(QUANTITIES))
    lun = e095[e095["kind"] == 0]
    a.errorbar(x - 0.15, lun["measured"] / lun["theory"], yerr=lun["std_error"] / np.abs(lun["theory"]),
               fmt="o", capsize=3, label="e = 0.95, 100 1/s")
    for k, (r, mk) in enumerate(zip(e07, ["s", "D"])):
        m = np.array([r["T"], r["P"], r["sxz"]])
        err = np.array([r["T_err"], r["P_err"], r["sxz_err"]])
        th = np.array([r["T_lun"], r["P_lun"], r["sxz_lun"]])
        a.errorbar(x + 0.1 + 0.1 * k, m / th, yerr=err / np.abs(th), fmt=mk, capsize=3,
                   label=f"e = 0.7, {r['shear_rate']:.0f} 1/s")
    a.axhline(1.0, color="k", lw=0.8)
    a.axhspan(0.94, 1.06, color="0.85", label="+- 6 % (e = 0.95 test)")
    a.fill_between([-0.4, 0.4], 0.68, 0.86, color="C1", alpha=0.12,
                   label="T window of the e = 0.7 test")
    # Where first-order theory's T lies against the Grad 13-moment solution of uniform shear, in
    # the dilute limit where both are exact to their order (docs/models/rheology.md):
    # T_Grad / T_Lun = 1 - (5/3)(1 - e)/(3 - e).
    for e, c in ((0.95, "C0"), (0.7, "C1")):
        a.hlines(1 - 5 / 3 * (1 - e) / (3 - e), -0.38, 0.38, colors=c, linestyles="--", lw=1.2,
                 label=f"Grad 13 moments / Lun, dilute, e = {e}")
    a.set_xticks(x, QUANTITIES)
    a.set_ylabel("measured / Lun et al. (1984)")
    a.set_title("Homogeneous shear, spheres, phi = 0.1")
    a.set_ylim(0.65, 1.22)
    a.legend(fontsize=6, ncol=2, loc="upper center")

    # Right: coordination number against omega_Enskog t_c.
    a = ax[1]
    z = e095[e095["kind"] == 1]
    pts = [(float(z["theory"][0]), float(z["measured"][0]), float(z["std_error"][0]),
            "o", "e = 0.95")]
    for r, mk in zip(e07, ["s", "D"]):
        pts.append((r["Z_enskog"], r["Z"], r["Z_err"], mk, f"e = 0.7, {r['shear_rate']:.0f} 1/s"))
    for th, m, err, mk, lab in pts:
        a.errorbar([th], [m], yerr=[err], fmt=mk, capsize=3, label=lab)
    top = 1.15 * max(max(p[0], p[1]) for p in pts)
    line = np.linspace(0, top, 2)
    a.plot(line, line, "k-", lw=0.8, label="Z = omega t_c")
    a.fill_between(line, 0.92 * line, 1.08 * line, color="0.85", label="+- 8 % (e = 0.95 test)")
    a.set_xlim(0, top)
    a.set_ylim(0, top)
    a.set_xlabel("Enskog collision frequency x Hooke contact duration")
    a.set_ylabel("measured coordination number Z")
    a.set_title("Contacts per grain")
    a.legend(fontsize=7)

    # Right: homogeneous cooling, T(t) against Haff's T0 / (1 + t / tau)^2.
    a = ax[2]
    h = load(folder, "haff_cooling")
    # the run ends at t = tau, where Haff's law has fallen to a quarter of T0
    tau, t0 = h["t"][-1], 4 * h["T_haff"][-1]
    a.plot(h["t"] / tau, h["T"] / t0, ".", ms=4, label="DEM, 2197 spheres, e = 0.9, phi = 0.1")
    a.plot(h["t"] / tau, h["T_haff"] / t0, "k-", lw=0.8,
           label="Haff: 1 / (1 + t / tau)^2, tau = 6 / ((1 - e^2) omega_Enskog)")
    a.set_xlabel("t / tau")
    a.set_ylabel("T / T0")
    a.set_title("Homogeneous cooling (collisional dissipation)")
    a.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(os.path.join(out, "rheology_spheres_kinetic_theory.png"), dpi=120)
    plt.close(fig)


if __name__ == "__main__":
    validation_run.plot_main(__doc__,
                             "RheologyValidation.LeesEdwards*:RheologyValidation.Dilute*:"
                             "RheologyValidation.HomogeneousCooling*",
                             [plot], OMP_NUM_THREADS="1")
