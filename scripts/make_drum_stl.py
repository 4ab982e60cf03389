#!/usr/bin/python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""Writes the binary STL of a closed drum with lifters (cases/dem/drum_lifters/drum.stl).

The drum: a cylinder of radius R about the y axis from y = 0 to y = L, cut into `segments`
flat panels, closed by two end plates (fans of triangles about the axis), with `lifters` bars
along the drum (height h, thickness t) standing on the inner wall. Units: metres.

    /usr/bin/python3 scripts/make_drum_stl.py cases/dem/drum_lifters/drum.stl
"""
import argparse
import math
import struct


def drum_triangles(R, L, segments, lifters, h, t):
    tris = []

    def ring(y):
        return [(R * math.cos(2 * math.pi * k / segments), y,
                 R * math.sin(2 * math.pi * k / segments)) for k in range(segments)]

    a, b = ring(0.0), ring(L)
    for k in range(segments):
        k1 = (k + 1) % segments
        tris += [(a[k], a[k1], b[k1]), (a[k], b[k1], b[k])]   # barrel
        tris += [((0, 0.0, 0), a[k1], a[k]), ((0, L, 0), b[k], b[k1])]  # end plates
    for j in range(lifters):
        phi = 2 * math.pi * (j + 0.5) / lifters
        radial = (math.cos(phi), 0.0, math.sin(phi))
        tangent = (-math.sin(phi), 0.0, math.cos(phi))
        # A bar from the wall (r = R, sunk 1 mm into it) to r = R - h, thickness t.
        def p(r, s, y):
            return (r * radial[0] + s * tangent[0], y, r * radial[2] + s * tangent[2])
        r0, r1 = R + 0.001, R - h
        for y0, y1 in ((0.0, L),):
            faces = [
                (p(r0, -t / 2, y0), p(r1, -t / 2, y0), p(r1, -t / 2, y1), p(r0, -t / 2, y1)),
                (p(r0, t / 2, y0), p(r0, t / 2, y1), p(r1, t / 2, y1), p(r1, t / 2, y0)),
                (p(r1, -t / 2, y0), p(r1, t / 2, y0), p(r1, t / 2, y1), p(r1, -t / 2, y1)),
            ]
            for q in faces:
                tris += [(q[0], q[1], q[2]), (q[0], q[2], q[3])]
    return tris


def write_binary_stl(path, tris, name):
    with open(path, "wb") as f:
        f.write(name.encode()[:80].ljust(80, b" "))
        f.write(struct.pack("<I", len(tris)))
        for a, b, c in tris:
            u = [b[i] - a[i] for i in range(3)]
            v = [c[i] - a[i] for i in range(3)]
            n = [u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]]
            ln = math.sqrt(sum(x * x for x in n)) or 1.0
            f.write(struct.pack("<3f", *[x / ln for x in n]))
            for p in (a, b, c):
                f.write(struct.pack("<3f", *p))
            f.write(struct.pack("<H", 0))


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("output")
    ap.add_argument("--radius", type=float, default=0.1)
    ap.add_argument("--length", type=float, default=0.06)
    ap.add_argument("--segments", type=int, default=96)
    ap.add_argument("--lifters", type=int, default=6)
    ap.add_argument("--lifter-height", type=float, default=0.015)
    ap.add_argument("--lifter-thickness", type=float, default=0.006)
    a = ap.parse_args()
    tris = drum_triangles(a.radius, a.length, a.segments, a.lifters, a.lifter_height,
                          a.lifter_thickness)
    write_binary_stl(a.output, tris, "grainflow drum with lifters")
    print(f"{a.output}: {len(tris)} triangles")


if __name__ == "__main__":
    main()
