#!/usr/bin/python3
# SPDX-License-Identifier: GPL-3.0-or-later
# The grains of case.yaml: 4 x 6 random convex polygons (5-7 corners at jittered, evenly spread
# angles, circumradius 1.76-2.2 mm) on a 6.3 mm lattice jittered by 0.3 mm, from a fixed seed.
#   /usr/bin/python3 cases/fluid_fem/polygons_sedimenting/grains.py
# prints the `bodies:` entries (paste them into case.yaml); the gaps between neighbours stay
# above the repulsion range (0.75 mm). Other blocks of the same grains (tilting_box):
#   grains.py COLUMNS ROWS SPACING X0 Y0 JITTER [SEED]   (lengths in m; the lattice's first
#   centre; SEED another draw of grains, default 11)
import sys

import numpy as np

cols, rows, spacing, x0, y0, jitter, seed = 4, 6, 0.0063, 0.0052, 0.0060, 3e-4, 11
if len(sys.argv) in (7, 8):
    cols, rows = int(sys.argv[1]), int(sys.argv[2])
    spacing, x0, y0, jitter = (float(a) for a in sys.argv[3:7])
    if len(sys.argv) == 8:
        seed = int(sys.argv[7])
elif len(sys.argv) != 1:
    sys.exit("usage: grains.py [COLUMNS ROWS SPACING X0 Y0 JITTER [SEED]]")
rng = np.random.default_rng(seed)
lines = []
k = 0
for row in range(rows):
    for col in range(cols):
        cx = x0 + spacing * col + rng.uniform(-jitter, jitter)
        cy = y0 + spacing * row + rng.uniform(-jitter, jitter)
        n = int(rng.integers(5, 8))
        ang = np.sort((np.arange(n) + rng.uniform(-0.3, 0.3, n)) * 2 * np.pi / n + rng.uniform(0, 2*np.pi))
        r = 0.0022 * rng.uniform(0.8, 1.0, n)
        P = np.array([(cx + ri * np.cos(a), cy + ri * np.sin(a)) for ri, a in zip(r, ang)])
        assert all(np.cross(P[(i+1)%n]-P[i], P[(i+2)%n]-P[(i+1)%n]) > 0 for i in range(n))
        s = ", ".join(f"[{x:.5f}, {y:.5f}]" for x, y in P)
        lines.append(f"    - {{name: g{k:02d}, polygon: [{s}], density: 2500}}")
        k += 1
print("\n".join(lines))
