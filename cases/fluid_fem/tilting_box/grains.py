#!/usr/bin/python3
# SPDX-License-Identifier: GPL-3.0-or-later
# The grains of case.yaml: 6 x 5 random convex polygons (5-7 corners at jittered, evenly spread
# angles, circumradius 1.76-2.2 mm) on a 5 mm lattice jittered by 0.2 mm, from a fixed seed.
#   /usr/bin/python3 cases/fluid_fem/tilting_box/grains.py
# prints the `bodies:` entries (paste them into case.yaml); neighbours start 0.6 mm or more apart
# (the bed compacts in the first second, before the tilt).
import numpy as np

rng = np.random.default_rng(11)
lines = []
k = 0
for row in range(5):
    for col in range(6):
        cx = 0.0030 + 0.0050 * col + rng.uniform(-2e-4, 2e-4)
        cy = 0.0030 + 0.0050 * row + rng.uniform(-2e-4, 2e-4)
        n = int(rng.integers(5, 8))
        ang = np.sort((np.arange(n) + rng.uniform(-0.3, 0.3, n)) * 2 * np.pi / n + rng.uniform(0, 2 * np.pi))
        r = 0.0022 * rng.uniform(0.8, 1.0, n)
        P = np.array([(cx + ri * np.cos(a), cy + ri * np.sin(a)) for ri, a in zip(r, ang)])
        assert all(np.cross(P[(i + 1) % n] - P[i], P[(i + 2) % n] - P[(i + 1) % n]) > 0 for i in range(n))
        s = ", ".join(f"[{x:.5f}, {y:.5f}]" for x, y in P)
        lines.append(f"    - {{name: g{k:02d}, polygon: [{s}], density: 2500}}")
        k += 1
print("\n".join(lines))
