#!/usr/bin/python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""Plots of a rheology sweep table (sweep.csv, written by `grainflow sweep`), in the manner of
Mahajan et al. (2019): log-log granular temperature, pressure and shear stress against the
measured shear rate for each volume fraction (kinetic theory of volume-equivalent spheres dashed),
apparent friction and viscosity, -N2/N1, and the alignment angle against shear rate and volume
fraction, and (for tables that have them) the coordination number and the contact fabric, and
for runs between shear walls the momentum balance (the layer's stresses over the walls'
tractions: 1 in a steady flow).

Usage: plot_sweep.py sweep.csv OUTPUT_FOLDER [PREFIX] [--only FIGURE[,FIGURE...]]
writes OUTPUT_FOLDER/PREFIX_stresses.png, PREFIX_friction_normal_stress.png and (when the grains
have an orientation order) PREFIX_alignment.png and (when the table has the contact columns)
PREFIX_contacts.png and (when the table has finite wall tractions: shear walls)
PREFIX_momentum_balance.png; PREFIX defaults to "rheology", a trailing "_"
is dropped (PREFIX rheology_rods_ gives rheology_rods_stresses.png), and OUTPUT_FOLDER is
created if missing. --only draws the named figures (stresses, friction_normal_stress, alignment,
contacts, momentum_balance) and no others. `grainflow sweep` calls it on its own table."""
import os
import sys

import numpy as np

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


FIGURES = ["stresses", "friction_normal_stress", "alignment", "contacts", "momentum_balance"]


def load(path):
    d = np.genfromtxt(path, delimiter=",", names=True, dtype=None, encoding="utf-8")
    return np.atleast_1d(d)


def groups(d):
    """Runs grouped by nominal volume fraction (NaN: one group), sorted by shear rate."""
    phis = d["volume_fraction_nominal"]
    keys = sorted(set(np.where(np.isnan(phis), -1.0, phis)))
    for k in keys:
        sel = np.where(np.isnan(phis), -1.0, phis) == k
        sub = d[sel]
        sub = sub[np.argsort(sub["shear_rate"])]
        yield (None if k < 0 else k), sub


def errorbars(ax, x, y, e, **kw):
    ax.errorbar(x, y, yerr=np.where(np.isfinite(e), e, 0), capsize=2, **kw)


def save_against_rate(fig, axes, path):
    """Shear-rate axes (logarithmic where the rates span more than a factor 3, as a sweep's
    do; linear for one nominal rate, whose measured values lie within a few %) with grids, the
    legend in the first panel; writes and closes fig."""
    for ax in axes:
        lo, hi = ax.dataLim.intervalx
        if lo > 0 and hi > 3 * lo:
            ax.set_xscale("log")
        ax.set_xlabel("measured shear rate (1/s)")
        ax.grid(True, which="both", alpha=0.3)
    axes[0].legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def main():
    args = sys.argv[1:]
    only = None
    if "--only" in args:
        k = args.index("--only")
        if k + 1 >= len(args):
            sys.exit(__doc__)
        only = set(args[k + 1].split(","))
        unknown = only - set(FIGURES)
        if unknown:
            sys.exit(f"plot_sweep.py: --only {','.join(sorted(unknown))}: not one of "
                     f"{', '.join(FIGURES)}")
        del args[k:k + 2]
    if len(args) not in (2, 3):
        sys.exit(__doc__)
    table, out = args[0], args[1]
    prefix = args[2].rstrip("_") if len(args) > 2 else "rheology"

    def want(figure):
        return only is None or figure in only

    os.makedirs(out, exist_ok=True)
    d = load(table)
    colors = plt.cm.viridis(np.linspace(0, 0.9, max(1, len(list(groups(d))))))

    if want("stresses"):
        # 1. T, P, -sigma_xz against shear rate (log-log), kinetic theory dashed.
        fig, axes = plt.subplots(1, 3, figsize=(14, 4.2))
        for (phi, g), c in zip(groups(d), colors):
            lab = "measured" if phi is None else f"phi = {phi:g}"
            rate = np.abs(g["shear_rate"])
            for ax, q, sign in zip(axes, ["granular_temperature", "pressure", "sigma_xz"], [1, 1, -1]):
                errorbars(ax, rate, sign * g[q], g[q + "_err"], fmt="o-", color=c, label=lab)
                kt = sign * g[q + "_kt"]
                if np.any(np.isfinite(kt)):
                    ax.plot(rate, kt, "--", color=c, alpha=0.8)
        for ax, t in zip(axes, ["granular temperature T (m$^2$/s$^2$)", "pressure P (Pa)",
                                "shear stress $-\\sigma_{xz}$ (Pa)"]):
            ax.set_xscale("log")
            ax.set_yscale("log")
            ax.set_xlabel("measured shear rate (1/s)")
            ax.set_ylabel(t)
            ax.grid(True, which="both", alpha=0.3)
        axes[0].legend(fontsize=8, title="dashed: kinetic theory,\nvolume-equivalent spheres",
                       title_fontsize=7)
        fig.tight_layout()
        fig.savefig(f"{out}/{prefix}_stresses.png", dpi=110)
        plt.close(fig)

    if want("friction_normal_stress"):
        # 2. Apparent friction and viscosity; -N2/N1.
        fig, axes = plt.subplots(1, 3, figsize=(14, 4.2))
        for (phi, g), c in zip(groups(d), colors):
            lab = "measured" if phi is None else f"phi = {phi:g}"
            rate = np.abs(g["shear_rate"])
            errorbars(axes[0], rate, g["friction"], g["friction_err"], fmt="o-", color=c, label=lab)
            errorbars(axes[1], rate, g["viscosity"], g["viscosity_err"], fmt="o-", color=c, label=lab)
            with np.errstate(divide="ignore", invalid="ignore"):
                ratio = -g["N2"] / g["N1"]
                rerr = np.abs(ratio) * np.hypot(g["N2_err"] / g["N2"], g["N1_err"] / g["N1"])
            errorbars(axes[2], rate, ratio, rerr, fmt="o-", color=c, label=lab)
        axes[0].set_ylabel("apparent friction $|\\sigma_{xz}|/P$")
        axes[1].set_ylabel("viscosity $-\\sigma_{xz}/\\dot\\gamma$ (Pa s)")
        axes[1].set_yscale("log")
        axes[2].set_ylabel("$-N_2/N_1$")
        axes[2].axhline(0.5, color="k", lw=0.8, ls=":")
        save_against_rate(fig, axes, f"{out}/{prefix}_friction_normal_stress.png")

    # 3. Alignment angle against shear rate and against volume fraction (highest rate).
    if want("alignment") and np.any(np.abs(d["order_parameter"]) > 0):
        fig, axes = plt.subplots(1, 2, figsize=(10, 4.2))
        phis, angles, errs = [], [], []
        for (phi, g), c in zip(groups(d), colors):
            lab = "measured" if phi is None else f"phi = {phi:g}"
            errorbars(axes[0], np.abs(g["shear_rate"]), g["alignment_angle"],
                      g["alignment_angle_err"], fmt="o-", color=c, label=lab)
            top = np.argmax(np.abs(g["shear_rate"]))
            phis.append(g["volume_fraction"][top])
            angles.append(g["alignment_angle"][top])
            errs.append(g["alignment_angle_err"][top])
        axes[0].set_xscale("log")
        axes[0].set_xlabel("measured shear rate (1/s)")
        axes[0].legend(fontsize=8)
        errorbars(axes[1], np.array(phis), np.array(angles), np.array(errs), fmt="o-", color="k")
        axes[1].set_xlabel("measured volume fraction")
        for ax in axes:
            ax.set_ylabel("alignment angle (degrees)")
            ax.grid(True, alpha=0.3)
        fig.tight_layout()
        fig.savefig(f"{out}/{prefix}_alignment.png", dpi=110)
        plt.close(fig)

    # 4. Contacts (tables of builds that measure them): coordination number, the angle of the
    # contact fabric's major axis, and the fabric's anisotropies next to the normal stress
    # differences they feed (F_xx - F_zz with N1, F_zz - F_yy with N2).
    if want("contacts") and "coordination_number" in d.dtype.names:
        fig, axes = plt.subplots(1, 3, figsize=(14, 4.2))
        for (phi, g), c in zip(groups(d), colors):
            lab = "measured" if phi is None else f"phi = {phi:g}"
            rate = np.abs(g["shear_rate"])
            errorbars(axes[0], rate, g["coordination_number"], g["coordination_number_err"],
                      fmt="o-", color=c, label=lab)
            errorbars(axes[1], rate, g["fabric_angle"], g["fabric_angle_err"], fmt="o-",
                      color=c, label=lab)
            errorbars(axes[2], rate, g["F_xx"] - g["F_zz"],
                      np.hypot(g["F_xx_err"], g["F_zz_err"]), fmt="o-", color=c, label=lab)
            errorbars(axes[2], rate, g["F_zz"] - g["F_yy"],
                      np.hypot(g["F_zz_err"], g["F_yy_err"]), fmt="s--", color=c, mfc="none")
        axes[0].set_ylabel("coordination number Z")
        axes[0].set_yscale("log")
        axes[1].set_ylabel("major axis of the contact fabric (degrees)")
        axes[1].axhline(-45, color="k", lw=0.8, ls=":")
        axes[2].set_ylabel("fabric anisotropy: $F_{xx}-F_{zz}$ (o), $F_{zz}-F_{yy}$ (s)")
        axes[2].axhline(0, color="k", lw=0.8, ls=":")
        save_against_rate(fig, axes, f"{out}/{prefix}_contacts.png")

    # 5. Momentum balance between shear walls (tables with the walls' tractions): the layer's
    # sigma_xz and sigma_zz over the walls' tractions, 1 in a steady flow; a point off 1 by
    # more than its errors is a run that was not steady (or decaying: walls that slip).
    if (want("momentum_balance") and "wall_sigma_xz" in d.dtype.names
            and np.any(np.isfinite(d["wall_sigma_xz"]))):
        fig, axes = plt.subplots(1, 2, figsize=(10, 4.2))
        for (phi, g), c in zip(groups(d), colors):
            lab = "measured" if phi is None else f"phi = {phi:g}"
            rate = np.abs(g["shear_rate"])
            for ax, q in zip(axes, ["sigma_xz", "sigma_zz"]):
                w = "wall_" + q
                with np.errstate(divide="ignore", invalid="ignore"):
                    ratio = g[q] / g[w]
                    err = np.abs(ratio) * np.hypot(g[q + "_err"] / g[q], g[w + "_err"] / g[w])
                errorbars(ax, rate, ratio, err, fmt="o-", color=c, label=lab)
        axes[0].set_ylabel("$\\sigma_{xz}$ of the layer / walls' traction")
        axes[1].set_ylabel("$\\sigma_{zz}$ of the layer / walls' traction")
        for ax in axes:
            ax.axhline(1.0, color="k", lw=0.8, ls=":")
        save_against_rate(fig, axes, f"{out}/{prefix}_momentum_balance.png")


if __name__ == "__main__":
    main()
