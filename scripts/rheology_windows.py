#!/usr/bin/python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""Means of a shear run's rheology samples over consecutive strain windows, to see whether (and
where) a long run became steady. The run may be split over restarts: give its rheology.csv files
in order (`grainflow run --restart` writes the continuation into a new folder); samples are
concatenated and, where a later file repeats strains, the later samples win. Prints one row per
window (windows with fewer than 5 samples are left out); with --csv also appends them to a CSV
file (its header first when the file is new or empty), each row starting with --label, so that
several runs can be collected in one table (scripts/plot_cfd_dem.py --slip reads such a table).
Usage: rheology_windows.py [--width STRAIN] [--csv OUT.csv] [--label NAME] rheology.csv..."""
import argparse
import csv
import sys

import numpy as np

QUANTITIES = ["granular_temperature", "pressure", "sigma_xz", "order_parameter",
              "alignment_angle", "volume_fraction", "shear_rate"]
# Written since 2026-11-25 (CFD-DEM runs): shown when every file has them.
OPTIONAL = ["fluid_temperature", "slip_temperature"]


def load(paths):
    rows = {}
    for p in paths:
        with open(p, newline="") as f:
            for r in csv.DictReader(f):
                rows[round(float(r["strain"]), 9)] = r  # a restart's samples replace older ones
    strains = sorted(rows)
    names = QUANTITIES + [q for q in OPTIONAL if all(q in r for r in rows.values())]
    return np.array(strains), {q: np.array([float(rows[s][q]) for s in strains]) for q in names}


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("files", nargs="+")
    ap.add_argument("--width", type=float, default=2.0, help="strain per window (default 2)")
    ap.add_argument("--csv", help="also append the windows to this CSV file")
    ap.add_argument("--label", default="", help="first column of the CSV rows")
    a = ap.parse_args()
    strain, q = load(a.files)
    if len(strain) == 0:
        sys.exit("rheology_windows.py: no samples in " + " ".join(a.files))
    out = []
    k = 0
    while k * a.width < strain[-1]:
        # Bounds rounded as the strains are, so a sample at a bound falls in the window it ends.
        lo, hi = round(k * a.width, 9), round((k + 1) * a.width, 9)
        m = (strain > lo) & (strain <= hi)
        if m.sum() >= 5:
            out.append([lo, hi, int(m.sum())] + [v[m].mean() for v in q.values()])
        k += 1
    header = ["strain_from", "strain_to", "samples"] + list(q)
    print(" ".join(f"{h:>12.12}" for h in header))
    for r in out:
        print(" ".join(f"{v:12.4g}" for v in r))
    if a.csv:
        with open(a.csv, "a", newline="") as f:
            w = csv.writer(f)
            if f.tell() == 0:
                w.writerow(["run"] + header)
            for r in out:
                w.writerow([a.label] + [f"{v:.6g}" for v in r])


if __name__ == "__main__":
    main()
