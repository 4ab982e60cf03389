#!/usr/bin/python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""A quick look at a contact network without ParaView: the lines of contacts_NNNNNNNNN.vtp
(written with output.contacts_vtk) projected onto a plane, each drawn with a width and colour
that grow with its normal force F . n; grain pairs solid, grain-wall contacts dotted.

Usage: /usr/bin/python3 scripts/plot_force_chains.py CONTACTS_VTP [--out PNG]
           [--plane xz|xy|yz] [--strongest FRACTION]

--plane: the two coordinates drawn (default xz: flow and gradient of a shear box);
--strongest: draw only that fraction of the contacts, the strongest (default 1: all);
--out: the PNG (default: the .vtp's name with .png; its folder is created if missing). Lines that cross a periodic boundary run to
the partner's image outside the box, as in the file. Uses Debian's python3-vtk9, python3-numpy
and python3-matplotlib."""
import argparse
import os
import sys

import numpy as np

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
from matplotlib.collections import LineCollection  # noqa: E402
from matplotlib.colors import LinearSegmentedColormap, Normalize  # noqa: E402

# inferno reversed, without its palest sixth (weak contacts stay visible on white)
CMAP = LinearSegmentedColormap.from_list("chains", plt.cm.inferno_r(np.linspace(0.15, 1, 256)))


def read_network(path):
    """Line end points (n, 2, 3), fn (n) and wall index (n; -1 for a grain pair) of the file."""
    import vtk
    from vtk.util.numpy_support import vtk_to_numpy

    reader = vtk.vtkXMLPolyDataReader()
    reader.SetFileName(path)
    reader.Update()
    data = reader.GetOutput()
    n = data.GetNumberOfLines()
    if n == 0:
        return np.zeros((0, 2, 3)), np.zeros(0), np.zeros(0, dtype=int)
    points = vtk_to_numpy(data.GetPoints().GetData()).reshape(-1, 3)
    conn = vtk_to_numpy(data.GetLines().GetConnectivityArray()).reshape(-1, 2)
    cells = data.GetCellData()
    return (points[conn], vtk_to_numpy(cells.GetArray("fn")),
            vtk_to_numpy(cells.GetArray("wall")).astype(int))


def main():
    ap = argparse.ArgumentParser(description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("vtp", metavar="CONTACTS_VTP")
    ap.add_argument("--out", metavar="PNG")
    ap.add_argument("--plane", choices=["xz", "xy", "yz"], default="xz")
    ap.add_argument("--strongest", type=float, default=1.0, metavar="FRACTION")
    a = ap.parse_args()
    if not 0 < a.strongest <= 1:
        sys.exit("plot_force_chains.py: --strongest must be in (0, 1]")
    if not os.path.isfile(a.vtp):
        sys.exit(f"plot_force_chains.py: no file '{a.vtp}'")
    ends, fn, wall = read_network(a.vtp)
    axes = ["xyz".index(c) for c in a.plane]
    out = a.out or os.path.splitext(a.vtp)[0] + ".png"
    os.makedirs(os.path.dirname(os.path.abspath(out)), exist_ok=True)

    fig, ax = plt.subplots(figsize=(8, 5.5))
    if len(fn) > 0:
        order = np.argsort(fn)
        keep = order[len(order) - max(1, int(round(a.strongest * len(order)))):]
        segments = ends[keep][:, :, axes]
        f = np.clip(fn[keep], 0.0, None)
        scale = f.max() if f.max() > 0 else 1.0
        widths = 0.3 + 3.0 * f / scale
        norm = Normalize(0.0, scale)
        colours = CMAP(norm(f))
        styles = ["dotted" if w >= 0 else "solid" for w in wall[keep]]
        ax.add_collection(LineCollection(segments, linewidths=widths, colors=colours,
                                         linestyles=styles))
        ax.autoscale()
        fig.colorbar(plt.cm.ScalarMappable(cmap=CMAP, norm=norm), ax=ax,
                     label="normal force F . n (N)")
    ax.set_aspect("equal")
    ax.set_xlabel(f"{a.plane[0]} (m)")
    ax.set_ylabel(f"{a.plane[1]} (m)")
    shown = "all" if a.strongest >= 1 else f"the strongest {100 * a.strongest:g} %"
    ax.set_title(f"{os.path.basename(a.vtp)}: {len(fn)} contacts ({shown}; walls dotted)",
                 fontsize=9)
    fig.tight_layout()
    fig.savefig(out, dpi=120)
    plt.close(fig)
    print(f"plot written to {out}")


if __name__ == "__main__":
    main()
