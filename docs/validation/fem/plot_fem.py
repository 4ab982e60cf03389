#!/usr/bin/python3
# SPDX-License-Identifier: GPL-3.0-or-later
# Plots of the fluid_fem validation against Schaefer & Turek (1996): 2D-1 mesh convergence,
# 2D-2 and 2D-3 force histories with the reference values. Run with Debian's python3:
#   /usr/bin/python3 docs/validation/fem/plot_fem.py <results_2d1.csv> <st2.csv> <st3.csv>
import csv
import os
import sys

import matplotlib
import numpy as np

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from st_analysis import FEATFLOW_2D2_L6, analyse_2d2, analyse_2d3, load  # noqa: E402

HERE = os.path.dirname(os.path.abspath(__file__))


def plot_2d1(path):
    rows = [r for r in csv.DictReader(open(path)) if r["variant"] in ("full", "newton_mumps")]
    fig, ax = plt.subplots(figsize=(6, 4))
    for code, mk in (("grainflow", "o-"), ("dolfinx", "^--")):
        sel = [r for r in rows if r["code"] == code]
        n = [int(r["dofs"]) for r in sel]
        for q, c in (("cd_err", "C0"), ("cl_err", "C1"), ("dp_err", "C2")):
            ax.loglog(n, [max(abs(float(r[q])), 1e-9) for r in sel], mk, color=c,
                      label=f"{code} {dict(cd_err='C_D', cl_err='C_L', dp_err='dp')[q]}")
    ax.axhline(1e-3, color="k", lw=0.8, ls=":", label="0.1 %")
    ax.set_xlabel("unknowns")
    ax.set_ylabel("relative error vs reference")
    ax.set_title("2D-1 (Re = 20): mesh convergence")
    ax.legend(fontsize=7, ncol=2)
    ax.grid(True, which="both", alpha=0.3)
    fig.tight_layout()
    fig.savefig(os.path.join(HERE, "st_2d1_convergence.png"), dpi=120)


def plot_2d2(path):
    d = load(path)
    r = analyse_2d2(d)
    fig = plt.figure(figsize=(7, 9))
    gs = fig.add_gridspec(4, 1)
    axs = [fig.add_subplot(gs[0])]
    axs += [fig.add_subplot(gs[i], sharex=axs[0]) for i in (1, 2)] + [fig.add_subplot(gs[3])]
    m = d["t"] >= d["t"][-1] - 1.0
    for ax, q, lo, hi, lab in ((axs[0], "cd", 3.22, 3.24, "C_D"), (axs[1], "cl", 0.99, 1.01, "C_L"),
                               (axs[2], "dp", 2.46, 2.50, "dp")):
        ax.plot(d["t"][m], d[q][m], label="grainflow")
        if q != "dp":
            ax.axhspan(lo, hi, color="C1", alpha=0.3, label=f"reference max {lo}-{hi}")
        else:
            ax.axhspan(lo, hi, color="C1", alpha=0.3, label=f"reference dp(t0 + T/2) {lo}-{hi}")
        if q + "_max" in FEATFLOW_2D2_L6:
            ax.axhline(FEATFLOW_2D2_L6[q + "_max"], color="k", lw=0.8, ls="--",
                       label=f"FEATFLOW 2014, level 6: max {FEATFLOW_2D2_L6[q + '_max']}")
        ax.set_ylabel(lab)
        ax.legend(fontsize=7, loc="lower right")
    # one lift maximum against both references, magnified (the last in the window)
    tm = d["t"][m][np.argmax(np.where(d["t"][m] > d["t"][-1] - 0.4, d["cl"][m], -np.inf))]
    near = np.abs(d["t"] - tm) < 0.04
    axs[3].plot(d["t"][near], d["cl"][near], label="grainflow")
    axs[3].axhspan(0.99, 1.01, color="C1", alpha=0.3, label="reference max 0.99-1.01")
    axs[3].axhline(FEATFLOW_2D2_L6["cl_max"], color="k", lw=0.8, ls="--", label="FEATFLOW 2014, level 6")
    axs[3].set_ylim(0.97, 1.015)
    axs[3].set_ylabel("C_L near a maximum")
    axs[3].legend(fontsize=7, loc="lower right")
    axs[0].set_title(f"2D-2 (Re = 100): St = {r['St']:.4f} (ref 0.295-0.305), C_D,max = {r['cd_max']:.4f}, "
                     f"C_L,max = {r['cl_max']:.4f}, dp = {r['dp_half']:.4f}\n"
                     f"against FEATFLOW level 6: period {100 * (r['period'] / FEATFLOW_2D2_L6['period'] - 1):+.2f} %, "
                     f"C_D,max {100 * (r['cd_max'] / FEATFLOW_2D2_L6['cd_max'] - 1):+.3f} %, "
                     f"C_L,max {100 * (r['cl_max'] / FEATFLOW_2D2_L6['cl_max'] - 1):+.2f} %", fontsize=8)
    axs[2].set_xlabel("t [s]")
    axs[3].set_xlabel("t [s]")
    fig.tight_layout()
    fig.savefig(os.path.join(HERE, "st_2d2.png"), dpi=120)
    return r


def plot_2d3(path):
    d = load(path)
    r = analyse_2d3(d)
    fig, axs = plt.subplots(3, 1, figsize=(7, 7), sharex=True)
    axs[0].plot(d["t"], d["cd"], label="grainflow")
    axs[0].plot([3.93625], [2.950921575], "r*", ms=10, label="reference max")
    axs[1].plot(d["t"], d["cl"], label="grainflow")
    axs[1].plot([5.693125], [0.47795], "r*", ms=10, label="reference max")
    axs[2].plot(d["t"], d["dp"], label="grainflow")
    axs[2].plot([8.0], [-0.1116], "r*", ms=10, label="reference dp(8)")
    for ax, lab in zip(axs, ("C_D", "C_L", "dp")):
        ax.set_ylabel(lab)
        ax.legend(fontsize=7)
        ax.grid(alpha=0.3)
    axs[0].set_title(f"2D-3: C_D,max {r['cd_max']:.5f} ({100 * r['cd_err']:+.3f} %), C_L,max {r['cl_max']:.4f} "
                     f"({100 * r['cl_err']:+.2f} %), dp(8) {r['dp_end']:.4f} ({100 * r['dp_err']:+.1f} %)", fontsize=8)
    axs[2].set_xlabel("t [s]")
    fig.tight_layout()
    fig.savefig(os.path.join(HERE, "st_2d3.png"), dpi=120)
    return r


if __name__ == "__main__":
    if len(sys.argv) > 1 and os.path.exists(sys.argv[1]):
        plot_2d1(sys.argv[1])
    if len(sys.argv) > 2 and os.path.exists(sys.argv[2]):
        print("2D-2:", plot_2d2(sys.argv[2]))
    if len(sys.argv) > 3 and os.path.exists(sys.argv[3]):
        print("2D-3:", plot_2d3(sys.argv[3]))
