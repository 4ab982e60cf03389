#!/usr/bin/python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""Test of scripts/contact_stress.py on the contact network of a short run.

Usage (how CTest calls it):

    /usr/bin/python3 tests/python/test_contact_stress.py GRAINFLOW_BINARY SOURCE_DIR

Runs cases/rheology/lees_edwards_spheres (phi = 0.35, soft contacts k = 600 N/m so that ~100
pairs touch at a time, 2000 steps) with output.contacts_csv at every rheology sample, then the
script over the whole periodic box. Checks: for smooth spheres the branch vector lies along the
normal, so the "offset" part vanishes (below 1e-9 of the pressure: round-off of the products);
the script's collisional pressure and N1, N2 over all files equal the means of the run's own
rheology.csv samples at the same steps (pressure_collisional, N1_collisional, N2_collisional)
to 1e-6 relative (the CSV's shortest round-trip numbers summed in another order); a step past
the last file is an error.

Exit codes: 0 passed, 1 a check failed, 2 bad usage, 77 skipped (numpy not importable)."""
import os
import re
import subprocess
import sys
import tempfile

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from checks import Checks  # noqa: E402

check = Checks()
if len(sys.argv) != 3:
    print(__doc__)
    sys.exit(2)
try:
    import numpy as np
except ImportError:
    print("numpy not importable: skipped")
    sys.exit(77)

GF, SRC = sys.argv[1], sys.argv[2]
SCRIPT = os.path.join(SRC, "scripts", "contact_stress.py")
CASE = os.path.join(SRC, "cases", "rheology", "lees_edwards_spheres", "case.yaml")
BOX = (0.072, 0.048, 0.048)

with tempfile.TemporaryDirectory() as tmp:
    out = os.path.join(tmp, "run")
    r = subprocess.run([GF, "run", CASE, "--output", out, "--steps", "2000",
                        "--set", "particles[0].fill.volume_fraction=0.35",
                        "--set", "contacts[0].stiffness=600", "--set", "shear.rate=400",
                        "--set", "time.step=1.0e-6", "--set", "output.vtk.every=0",
                        "--set", "analysis.rheology.every=2.0e-4",
                        "--set", "output.contacts_csv.every=2.0e-4"],
                       capture_output=True, text=True, timeout=300)
    check(r.returncode == 0, f"grainflow run: {r.stderr[-2000:]}")
    s = subprocess.run([sys.executable, SCRIPT, out, "--layer", "-1", "1", "--volume",
                        str(BOX[0] * BOX[1] * BOX[2]), "--from-step", "200"],
                       capture_output=True, text=True, timeout=300)
    check(s.returncode == 0, f"contact_stress.py: {s.stderr}")
    parts = {}
    for line in s.stdout.splitlines():
        m = re.match(r"(total|central|offset)\s+(.*)", line)
        if m:
            nums = re.findall(r"(s_xx|s_yy|s_zz|s_xz|P|N1|N2)\s+(\S+)", m.group(2))
            parts[m.group(1)] = {k: float(v) for k, v in nums}
    check(set(parts) == {"total", "central", "offset"}, f"three parts printed: {s.stdout}")
    if len(parts) == 3:
        p = parts["total"]["P"]
        check(p > 0, f"positive collisional pressure: {p}")
        off = max(abs(v) for v in parts["offset"].values())
        check(off < 1e-9 * p, f"spheres: no offset part ({off} against P = {p})")
        # The run's own samples at the steps of the files (every 200 steps from 200 on; the
        # layer is the whole box, the volume the box's).
        rh = np.genfromtxt(os.path.join(out, "rheology.csv"), delimiter=",", names=True)
        steps = np.rint(rh["time"] / 1.0e-6).astype(int)
        sel = steps >= 200
        for key, col in [("P", "pressure_collisional"), ("N1", "N1_collisional"),
                         ("N2", "N2_collisional")]:
            ref = float(np.mean(rh[col][sel]))
            got = parts["total"][key]
            check(abs(got - ref) <= 1e-6 * abs(p), f"{key}: script {got}, rheology.csv {ref}")
    bad = subprocess.run([sys.executable, SCRIPT, out, "--layer", "-1", "1", "--area", "1",
                          "--from-step", "999999"], capture_output=True, text=True, timeout=60)
    check(bad.returncode != 0 and "no contacts_" in bad.stderr,
          f"no files from that step is an error: {bad.returncode} {bad.stderr}")

check.exit()
