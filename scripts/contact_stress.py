#!/usr/bin/python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""Collisional stress of a layer from a run's contact network (contacts_NNNNNNNNN.csv, written
with output.contacts_csv), split by how each contact's branch vector b (from the centre of j to
the centre of i) lies against its normal n:

    sigma_c = (1/V) sum b (x) F
            = (1/V) sum (b . n)(F . n) n (x) n      "central": what spheres would give
            + the rest                              "offset": b off the normal (elongated grains)
                                                    and tangential forces

Usage: /usr/bin/python3 scripts/contact_stress.py RUN_DIR --layer ZLO ZHI (--area A | --volume V)
           [--from-step N]

Contacts count when their contact point has ZLO <= z < ZHI (m); V = A (ZHI - ZLO), A the box's
cross-section normal to z (m^2), or V as given (a periodic box whose contacts across the z
boundary have their points outside it: a layer wider than the box and V the box's volume). Averages over the files from step N on (default all), and
prints for each part the stress components (Pa), pressure, N1 = s_xx - s_zz and
N2 = s_zz - s_yy, also over the total collisional pressure; with the contact fabric <n n> and
the coordination per contact. Compressive positive, as rheology.csv. Uses Debian's
python3-numpy."""
import argparse
import glob
import os
import re
import sys

import numpy as np


def parts_of(path, zlo, zhi, volume):
    d = np.atleast_1d(np.genfromtxt(path, delimiter=",", names=True))
    if d.dtype.names is None or d.size == 0:
        z = np.zeros((3, 3))
        return z, z, z, 0
    d = d[(d["z"] >= zlo) & (d["z"] < zhi)]
    b = np.stack([d["bx"], d["by"], d["bz"]], 1)
    f = np.stack([d["fx"], d["fy"], d["fz"]], 1)
    n = np.stack([d["nx"], d["ny"], d["nz"]], 1)
    total = np.einsum("ka,kb->ab", b, f) / volume
    central = np.einsum("k,ka,kb->ab", np.sum(b * n, 1) * np.sum(f * n, 1), n, n) / volume
    return total, central, np.einsum("ka,kb->ab", n, n), len(d)


def main():
    ap = argparse.ArgumentParser(description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("run", metavar="RUN_DIR")
    ap.add_argument("--layer", nargs=2, type=float, metavar=("ZLO", "ZHI"), required=True)
    size = ap.add_mutually_exclusive_group(required=True)
    size.add_argument("--area", type=float, metavar="A")
    size.add_argument("--volume", type=float, metavar="V")
    ap.add_argument("--from-step", type=int, default=0, metavar="N")
    a = ap.parse_args()
    zlo, zhi = a.layer
    volume = a.volume if a.volume is not None else (a.area or 0) * (zhi - zlo)
    if not zhi > zlo or not volume > 0:
        sys.exit("contact_stress.py: need ZHI > ZLO and a positive area or volume")
    files = []
    for f in sorted(glob.glob(os.path.join(a.run, "contacts_*.csv"))):
        m = re.fullmatch(r"contacts_(\d+)\.csv", os.path.basename(f))
        if m and int(m.group(1)) >= a.from_step:
            files.append(f)
    if not files:
        sys.exit(f"contact_stress.py: no contacts_*.csv from step {a.from_step} in {a.run}")
    total, central, fabric, contacts = np.zeros((3, 3)), np.zeros((3, 3)), np.zeros((3, 3)), 0
    for f in files:
        t, c, nn, k = parts_of(f, zlo, zhi, volume)
        total += t
        central += c
        fabric += nn
        contacts += k
    total /= len(files)
    central /= len(files)
    pc = np.trace(total) / 3
    print(f"{len(files)} files, {contacts / len(files):.1f} contacts per file in the layer")
    for name, s in [("total", total), ("central", central), ("offset", total - central)]:
        n1, n2 = s[0, 0] - s[2, 2], s[2, 2] - s[1, 1]
        print(f"{name:8s} s_xx {s[0, 0]:.8g} s_yy {s[1, 1]:.8g} s_zz {s[2, 2]:.8g} "
              f"s_xz {0.5 * (s[0, 2] + s[2, 0]):.8g} P {np.trace(s) / 3:.8g} "
              f"N1 {n1:.8g} N2 {n2:.8g}"
              + (f"  N1/P_c {n1 / pc:+.3f} N2/P_c {n2 / pc:+.3f}" if pc != 0 else ""))
    if contacts:
        fab = fabric / contacts
        print(f"fabric   F_xx {fab[0, 0]:.4f} F_yy {fab[1, 1]:.4f} F_zz {fab[2, 2]:.4f} "
              f"F_xz {fab[0, 2]:.4f}")


if __name__ == "__main__":
    main()
