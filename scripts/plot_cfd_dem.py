#!/usr/bin/python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""Plots of the CFD-DEM validation (tests/validation/test_cfd_dem_validation.cpp) and of the
shear box of rods in air and water against the dry box (Mahajan et al. 2019).

Usage:
  /usr/bin/python3 scripts/plot_cfd_dem.py [--out DIR] [BUILD_DIR]
      runs gf_validation_tests --gtest_filter='CfdDem*' with GF_VALIDATION_OUT set and writes
      docs/validation/cfd_dem_ergun.png and cfd_dem_hindered_settling.png;
  /usr/bin/python3 scripts/plot_cfd_dem.py [--out DIR] --shear DRY.csv AIR.csv WATER.csv
      reads three sweep.csv tables of `grainflow sweep` (cases/rheology/shear_box_rods,
      cases/cfd_dem/shear_box_rods_air, .../shear_box_rods_water) and writes
      docs/validation/cfd_dem_shear_box_temperature.png and cfd_dem_shear_box_stresses.png;
  /usr/bin/python3 scripts/plot_cfd_dem.py [--out DIR] --slip WINDOWS.csv
      reads strain windows of water runs (scripts/rheology_windows.py --csv, labels
      phi_<phi>_rate_<rate>) and writes docs/validation/cfd_dem_shear_box_slip.png: T, the fluid
      temperature T_f and the slip temperature T_s against phi per shear rate (mean of each
      run's later half of windows).
  /usr/bin/python3 scripts/plot_cfd_dem.py [--out DIR] --coupling DRY.csv WATER.csv CELL.csv
      reads the dry and water sweep.csv tables and a water sweep run with CFDEMcoupling's
      coupling choices (cell-value reads, centre-in-cell fluid fraction, its rate from the
      difference, drag only) and writes docs/validation/cfd_dem_shear_box_water_coupling.png: T
      against the measured shear rate per phi for both couplings, the dry box as thin lines.
--out DIR writes the plots into DIR (created if missing) instead of docs/validation.
Uses Debian's python3-numpy and python3-matplotlib."""
import os

import numpy as np

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

import validation_run  # noqa: E402

ROOT = validation_run.ROOT
OUT = validation_run.VALIDATION_DIR


def load(path):
    return np.atleast_1d(np.genfromtxt(path, delimiter=",", names=True, dtype=None,
                                       encoding="utf-8"))


def ergun(folder, out):
    d = load(os.path.join(folder, "cfd_dem_min_fluidisation.csv"))
    fixed = d[d["ergun_dp"] > 0]
    fluid = d[d["ergun_dp"] == 0]
    # Ergun is a U + b U^2 at fixed voidage: the two coefficients from the test's own values.
    A = np.column_stack([fixed["u"], fixed["u"] ** 2])
    (a, b), *_ = np.linalg.lstsq(A, fixed["ergun_dp"], rcond=None)
    w = fixed["w"][0]
    u_mf = (-a + np.sqrt(a * a + 4 * b * w)) / (2 * b)
    # Measured U_mf: where the line through the fixed-bed points meets the bed weight.
    (am, bm), *_ = np.linalg.lstsq(A, fixed["dp"], rcond=None)
    u_mf_meas = (-am + np.sqrt(am * am + 4 * bm * w)) / (2 * bm)
    u = np.linspace(0, 1.15 * max(d["u"]), 200)
    fig, ax = plt.subplots(figsize=(6.4, 4.4))
    ax.plot(u * 100, a * u + b * u * u, "k-", lw=1, label="Ergun (eps = %.4f)" % fixed["eps"][0])
    ax.fill_between(u * 100, 0.9 * (a * u + b * u * u), 1.1 * (a * u + b * u * u), color="0.88",
                    label="Ergun +- 10 %")
    ax.axhline(w, color="tab:gray", ls="--", lw=1, label="bed weight / area")
    ax.plot(fixed["u"] * 100, fixed["dp"], "o", color="tab:blue", label="grainflow, fixed bed")
    ax.plot(fluid["u"] * 100, fluid["dp"], "s", color="tab:red", label="grainflow, fluidised")
    ax.axvline(u_mf * 100, color="k", ls=":", lw=1)
    ax.axvline(u_mf_meas * 100, color="tab:blue", ls=":", lw=1)
    ax.set_xlabel("superficial velocity U (cm/s)")
    ax.set_ylabel("pressure drop (Pa)")
    ax.set_title("Packed bed: U_mf %.4f m/s vs Ergun %.4f m/s (%+.1f %%)"
                 % (u_mf_meas, u_mf, 100 * (u_mf_meas / u_mf - 1)), fontsize=10)
    ax.set_xlim(0, u[-1] * 100)
    ax.set_ylim(0, 1.25 * w)
    ax.legend(fontsize=8, loc="upper left")
    fig.tight_layout()
    fig.savefig(os.path.join(out, "cfd_dem_ergun.png"), dpi=120)
    plt.close(fig)


def hindered(folder, out):
    d = load(os.path.join(folder, "cfd_dem_hindered_settling.csv"))
    n = d["n"][0]
    eps = np.linspace(0.75, 1.0, 100)
    fig, ax = plt.subplots(figsize=(6.4, 4.4))
    ax.plot(eps, eps ** n, "k-", lw=1, label="Richardson-Zaki eps^n, n = %.3f" % n)
    ax.fill_between(eps, 0.85 * eps ** n, 1.15 * eps ** n, color="0.88", label="+- 15 %")
    # scheme: 0 divided deposit with the flux rate (the default), 1 trilinear and 2 smoothed
    # with their time derivative (older tables have no column: all divided).
    scheme = d["scheme"] if "scheme" in d.dtype.names else np.zeros(len(d), dtype=int)
    styles = [("o", "tab:blue", "grainflow, divided + flux (default)"),
              ("^", "tab:orange", "trilinear + derivative"),
              ("s", "tab:green", "smoothed + derivative")]
    for k, (marker, color, label) in enumerate(styles):
        rows = d[scheme == k]
        if len(rows) == 0:
            continue
        ax.plot(rows["eps"], rows["v"] / rows["vt"], marker, color=color, mfc="none", ms=7 + 2 * k,
                label=label)
    for r in d[scheme == 0]:
        ax.annotate("%+.1f %%" % (100 * (r["v"] / r["rz"] - 1)), (r["eps"], r["v"] / r["vt"]),
                    textcoords="offset points", xytext=(6, -10), fontsize=8)
    ax.set_xlabel("fluid fraction eps")
    ax.set_ylabel("settling speed / single-grain terminal speed")
    ax.set_title("Hindered settling of a homogeneous suspension", fontsize=10)
    ax.legend(fontsize=8, loc="upper left")
    fig.tight_layout()
    fig.savefig(os.path.join(out, "cfd_dem_hindered_settling.png"), dpi=120)
    plt.close(fig)


def shear(dry, air, water, out):
    media = [("dry", load(dry), "k", "o"), ("air", load(air), "tab:blue", "s"),
             ("water", load(water), "tab:red", "^")]
    phis = sorted(set(float(p) for p in media[0][1]["volume_fraction_nominal"]) &
                  set(float(p) for p in media[2][1]["volume_fraction_nominal"]))
    qty = [("granular_temperature", "T (m$^2$/s$^2$)"), ("pressure", "P (Pa)"),
           ("sigma_xz", "-sigma_xz (Pa)")]
    fig, ax = plt.subplots(len(qty), len(phis), figsize=(4 * len(phis), 3.2 * len(qty)),
                           squeeze=False)
    for j, phi in enumerate(phis):
        for i, (q, label) in enumerate(qty):
            a = ax[i][j]
            for name, d, col, mk in media:
                s = d[np.isclose(d["volume_fraction_nominal"], phi)]
                s = s[np.argsort(s["shear_rate"])]
                y = np.abs(s[q])
                a.errorbar(s["shear_rate"], y, yerr=s[q + "_err"], fmt=mk + "-", color=col,
                           capsize=2, label=name, ms=4)
            g = np.array([40, 200])
            ref = np.abs(media[0][1][np.isclose(media[0][1]["volume_fraction_nominal"], phi)][q])
            a.plot(g, np.nanmax(ref) * (g / 200.0) ** 2, ":", color="0.5", label="slope 2")
            a.set_xscale("log")
            a.set_yscale("log")
            a.set_xlabel("measured shear rate (1/s)")
            a.set_ylabel(label)
            if i == 0:
                a.set_title("phi = %.1f" % phi)
            a.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(os.path.join(out, "cfd_dem_shear_box_stresses.png"), dpi=110)
    plt.close(fig)

    fig, ax = plt.subplots(1, 2, figsize=(10, 4))
    rates = sorted(set(float(r) for r in media[2][1]["shear_rate_nominal"]))
    for name, d, col, mk in media:
        for k, rate in enumerate(rates):
            s = d[np.isclose(d["shear_rate_nominal"], rate)]
            s = s[np.argsort(s["volume_fraction"])]
            style = ["-", "--", ":"][k % 3]
            ax[0].errorbar(s["volume_fraction"], s["granular_temperature"],
                           yerr=s["granular_temperature_err"], fmt=mk + style, color=col,
                           capsize=2, ms=4, label="%s, %g 1/s" % (name, rate))
            ax[1].plot(s["volume_fraction"], s["alignment_angle"], mk + style, color=col, ms=4,
                       label="%s, %g 1/s" % (name, rate))
    ax[0].set_yscale("log")
    ax[0].set_xlabel("measured volume fraction")
    ax[0].set_ylabel("T (m$^2$/s$^2$)")
    ax[0].set_title("granular temperature against phi")
    ax[1].set_xlabel("measured volume fraction")
    ax[1].set_ylabel("alignment angle (deg)")
    ax[1].set_title("alignment against phi")
    for a in ax:
        a.legend(fontsize=6, ncol=3)
    fig.tight_layout()
    fig.savefig(os.path.join(out, "cfd_dem_shear_box_temperature.png"), dpi=110)
    plt.close(fig)


def slip(path, out):
    d = load(path)
    runs = {}
    for r in d:
        runs.setdefault(str(r["run"]), []).append(r)
    by_rate = {}
    for label, rows in runs.items():
        late = rows[len(rows) // 2:]  # the later half of the windows (at least the last)
        mean = {q: np.mean([r[q] for r in late]) for q in
                ("volume_fraction", "granular_temperature", "fluid_temperature",
                 "slip_temperature")}
        by_rate.setdefault(float(label.split("_rate_")[1]), []).append(mean)
    rates = sorted(by_rate)
    fig, ax = plt.subplots(1, len(rates), figsize=(3.6 * len(rates), 3.2))
    for a, rate in zip(np.atleast_1d(ax), rates):
        pts = sorted(by_rate[rate], key=lambda m: m["volume_fraction"])
        phi = [m["volume_fraction"] for m in pts]
        for q, name, mk in (("granular_temperature", "T", "o-"),
                            ("fluid_temperature", "T_f (fluid at the grains)", "s--"),
                            ("slip_temperature", "T_s (relative to the fluid)", "^-")):
            a.semilogy(phi, [m[q] for m in pts], mk, label=name)
        a.set_xlabel("measured phi")
        a.set_title(f"water, {rate:g} 1/s")
    np.atleast_1d(ax)[0].set_ylabel("m^2/s^2")
    np.atleast_1d(ax)[0].legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(os.path.join(out, "cfd_dem_shear_box_slip.png"), dpi=110)
    plt.close(fig)


def coupling(dry, water, cell, out):
    runs = [("water, trilinear reads (model A, the case's coupling)", load(water)),
            ("water, cell reads + centre-in-cell fraction (CFDEMcoupling's choices)", load(cell))]
    ref = load(dry)
    phis = sorted(set(float(p) for p in runs[1][1]["volume_fraction_nominal"]))
    colours = plt.cm.viridis(np.linspace(0, 0.9, len(phis)))
    fig, ax = plt.subplots(1, 2, figsize=(11, 4.4), sharey=True)
    for a, (title, d) in zip(ax, runs):
        for phi, col in zip(phis, colours):
            r = ref[np.isclose(ref["volume_fraction_nominal"], phi)]
            r = r[np.argsort(r["shear_rate"])]
            a.plot(r["shear_rate"], r["granular_temperature"], "-", color=col, lw=0.8, alpha=0.4)
            s = d[np.isclose(d["volume_fraction_nominal"], phi)]
            s = s[np.argsort(s["shear_rate"])]
            a.errorbar(s["shear_rate"], s["granular_temperature"],
                       yerr=s["granular_temperature_err"], fmt="o-", color=col, capsize=2, ms=4,
                       label="phi = %.1f" % phi)
        g = np.array([8.0, 200.0])
        a.plot(g, 1e-6 * g ** 2, ":", color="0.4", label="slope 2")
        a.set_xscale("log")
        a.set_yscale("log")
        a.set_xlabel("measured shear rate (1/s)")
        a.set_title(title, fontsize=9)
        a.legend(fontsize=7)
    ax[0].set_ylabel("T (m$^2$/s$^2$); thin lines: dry")
    fig.tight_layout()
    fig.savefig(os.path.join(out, "cfd_dem_shear_box_water_coupling.png"), dpi=110)
    plt.close(fig)


def main():
    ap = validation_run.parser(__doc__, out=False)
    mode = ap.add_mutually_exclusive_group()
    mode.add_argument("--shear", nargs=3, metavar=("DRY", "AIR", "WATER"),
                      help="three sweep.csv tables")
    mode.add_argument("--slip", metavar="WINDOWS", help="strain windows of rheology_windows.py")
    mode.add_argument("--coupling", nargs=3, metavar=("DRY", "WATER", "CELL"),
                      help="dry and water sweep.csv tables and a water sweep with cell reads")
    validation_run.add_out(ap)
    a = ap.parse_args()
    if (a.shear or a.slip or a.coupling) and a.build != ap.get_default("build"):
        ap.error("BUILD_DIR is not used with --shear, --slip or --coupling")
    os.makedirs(a.out, exist_ok=True)
    if a.slip:
        slip(a.slip, a.out)
        return
    if a.shear:
        shear(*a.shear, a.out)
        return
    if a.coupling:
        coupling(*a.coupling, a.out)
        return
    with validation_run.validation_run(a.build, "CfdDem*") as tmp:
        ergun(tmp, a.out)
        hindered(tmp, a.out)
    shown = os.path.relpath(OUT, ROOT) if a.out == OUT else a.out
    print(f"wrote {shown}/cfd_dem_ergun.png, cfd_dem_hindered_settling.png")


if __name__ == "__main__":
    main()
