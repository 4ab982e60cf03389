#!/usr/bin/python3
# SPDX-License-Identifier: GPL-3.0-or-later
# Turns bench/fem/results_2d1.csv into bench/RESULTS-fem.md and an accuracy-vs-time plot.
import csv
import os
import platform
import sys

import numpy as np


def main(src, dst):
    rows = list(csv.DictReader(open(src)))
    lines = []
    lines.append("# fluid_fem vs dolfinx: Schaefer-Turek 2D-1 (steady, Re = 20)\n")
    lines.append("Same machine, same run, one thread each; the same CGAL meshes (curved P2 cells) for both;")
    lines.append("P2-P1 Taylor-Hood, Newton to a relative increment of 1e-10. grainflow: UMFPACK (reference")
    lines.append("BLAS); `full` = a new LU every Newton step, `reuse` = chord steps with the LU kept while the")
    lines.append("increments contract by 0.3 or better, `nested` = the same on a mesh 2x coarser first (its")
    lines.append("LU count is included), then chord steps from the interpolated solution (the default of")
    lines.append("`fluid_fem` for steady cases). dolfinx 0.5.2 (Debian python3-dolfinx): its NewtonSolver with")
    lines.append("MUMPS LU (PETSc), forces by the same residual (reaction) functional. Times are the best of")
    lines.append("the repeats; grainflow's include meshing (and the coarse mesh for `nested`), dolfinx's exclude")
    lines.append("reading the mesh and the form compilation (JIT cache warmed first).")
    lines.append(f"Machine: {platform.node()}, {os.cpu_count()} cores shared with other jobs (load varies).\n")
    lines.append("| code | variant | cells | unknowns | Newton it. | LU fact. | C_D rel. err | C_L rel. err | dp rel. err | t_solve [s] | t_total [s] |")
    lines.append("|---|---|---|---|---|---|---|---|---|---|---|")
    for r in rows:
        lines.append(f"| {r['code']} | {r['variant']} | {r['cells']} | {r['dofs']} | {r['newton_it']} | {r['factorizations']} | "
                     f"{float(r['cd_err']):.2e} | {float(r['cl_err']):.2e} | {float(r['dp_err']):.2e} | "
                     f"{float(r['t_solve']):.3f} | {float(r['t_total']):.3f} |")
    lines.append("")
    lines.append("Ratio of total time to solution, dolfinx / grainflow (same mesh, hence the same accuracy):\n")
    lines.append("| cells | grainflow full | grainflow reuse | grainflow nested | dolfinx | ratio (full) | ratio (reuse) | ratio (nested) |")
    lines.append("|---|---|---|---|---|---|---|---|")
    by = {}
    for r in rows:
        by.setdefault(r["h_body"], {})[(r["code"], r["variant"])] = r
    for hb, d in by.items():
        try:
            f = float(d[("grainflow", "full")]["t_total"])
            u = float(d[("grainflow", "reuse")]["t_total"])
            n = float(d[("grainflow", "nested")]["t_total"])
            x = float(d[("dolfinx", "newton_mumps")]["t_total"])
            lines.append(f"| {d[('grainflow', 'full')]['cells']} | {f:.3f} | {u:.3f} | {n:.3f} | {x:.3f} | "
                         f"{x / f:.2f} | {x / u:.2f} | {x / n:.2f} |")
        except KeyError:
            pass
    lines.append("")
    lines.append("Plot: `bench/fem/accuracy_vs_time_2d1.png`. Regenerate: `bench/fem/run_2d1_comparison.sh build/fem 2`.")
    lines.append("Unsteady runs (2D-2, 2D-3) and the effect of reusing the LU across BDF steps:")
    lines.append("`docs/models/fluid_fem_status.md`.")
    open(dst, "w").write("\n".join(lines) + "\n")
    try:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
        fig, axs = plt.subplots(1, 3, figsize=(12, 3.8))
        for ax, q, name in zip(axs, ("cd_err", "cl_err", "dp_err"), ("C_D", "C_L", "dp")):
            for key, style in ((("grainflow", "full"), "o-"), (("grainflow", "reuse"), "s-"),
                               (("grainflow", "nested"), "D-"), (("dolfinx", "newton_mumps"), "^--")):
                sel = [r for r in rows if (r["code"], r["variant"]) == key]
                ax.loglog([float(r["t_total"]) for r in sel], [abs(float(r[q])) for r in sel], style,
                          label=" ".join(key))
            ax.set_xlabel("time to solution [s]")
            ax.set_ylabel(f"|{name} error| (relative)")
            ax.grid(True, which="both", alpha=0.3)
        axs[0].legend(fontsize=8)
        fig.suptitle("Schaefer-Turek 2D-1: accuracy vs time (4 meshes, 9k-228k unknowns)")
        fig.tight_layout()
        fig.savefig(os.path.join(os.path.dirname(os.path.abspath(src)), "accuracy_vs_time_2d1.png"), dpi=110)
    except ImportError:
        pass


if __name__ == "__main__":
    main(sys.argv[1], sys.argv[2])
