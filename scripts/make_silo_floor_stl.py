#!/usr/bin/python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""Writes the binary STL of a flat silo floor with a central circular orifice
(cases/dem/silo/floor.stl).

The floor: the annulus between the orifice's circle (radius r, `segments` straight sides with
their corners on the circle) and an outer circle of radius R, in the plane z = 0, as a strip of
quadrilaterals split into triangles. Units: metres.

    /usr/bin/python3 scripts/make_silo_floor_stl.py cases/dem/silo/floor.stl --orifice 0.012 \\
        --outer 0.036
"""
import argparse
import math
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.realpath(__file__)))
from make_drum_stl import write_binary_stl  # noqa: E402


def floor_triangles(r, R, segments):
    def ring(radius):
        return [(radius * math.cos(2 * math.pi * k / segments),
                 radius * math.sin(2 * math.pi * k / segments), 0.0) for k in range(segments)]

    inner, outer = ring(r), ring(R)
    tris = []
    for k in range(segments):
        k1 = (k + 1) % segments
        tris += [(inner[k], outer[k], outer[k1]), (inner[k], outer[k1], inner[k1])]
    return tris


def main():
    ap = argparse.ArgumentParser(description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("output")
    ap.add_argument("--orifice", type=float, default=0.012, help="orifice radius r, m")
    ap.add_argument("--outer", type=float, default=0.036, help="outer radius R, m")
    ap.add_argument("--segments", type=int, default=64)
    a = ap.parse_args()
    if not 0 < a.orifice < a.outer:
        raise SystemExit("expected 0 < --orifice < --outer")
    tris = floor_triangles(a.orifice, a.outer, a.segments)
    write_binary_stl(a.output, tris, f"silo floor, orifice radius {a.orifice} m")
    print(f"{a.output}: {len(tris)} triangles")


if __name__ == "__main__":
    main()
