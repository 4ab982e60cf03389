#!/usr/bin/python3
# SPDX-License-Identifier: GPL-3.0-or-later
# Schaefer-Turek 2D-2 (Re = 100, periodic) with dolfinx (Debian python3-dolfinx, P2-P1, BDF2 with
# a fixed step, Newton with MUMPS LU) on a mesh written by gf_fem_bench_st_2d1 (same nodes, same
# curved P2 cells): an independent implementation of the discretisation grainflow's
# gf_fem_bench_st_unsteady uses, for cross-checking C_D, C_L and dp on the same mesh and step.
# Start from rest, inflow ramped over 1 s by (1 - cos(pi t)) / 2 (as st_unsteady), first step
# BDF1. Forces from the residual of the momentum equations (reaction), like grainflow's.
# Usage: /usr/bin/python3 dolfinx_2d2.py mesh.txt dt t_end out.csv [degree]   (CSV: t,cd,cl,dp)
# degree 3 runs P3-P2 Taylor-Hood instead of P2-P1: a higher-order discretisation on the same
# mesh, to tell the P2-P1 discretisation error from the continuum value.
import sys
import time

import numpy as np
import ufl

import dolfinx.fem.petsc
from dolfinx import fem, geometry
from dolfinx_st import (H, cylinder_unit_velocity, newton_mumps, read_mesh, taylor_hood,
                        velocity_bcs)


def main(path, dt, t_end, out, degree=2):
    x, cells = read_mesh(path)
    n_cells = len(cells)
    msh, W, V = taylor_hood(x, cells, degree)
    u_max = 1.5

    def ramp(t):
        return 0.5 * (1 - np.cos(np.pi * t)) if t < 1.0 else 1.0

    inflow = fem.Function(V)
    bcs = velocity_bcs(W, V, inflow)

    w = fem.Function(W)
    w_n = fem.Function(W)
    w_nm1 = fem.Function(W)
    u, p = ufl.split(w)
    u_n, _ = ufl.split(w_n)
    u_nm1, _ = ufl.split(w_nm1)
    v, q = ufl.TestFunctions(W)
    rho, mu = 1.0, 1e-3
    # BDF coefficients: du/dt = (a0 u + a1 u_n + a2 u_nm1) / dt; BDF1 for the first step.
    a0, a1, a2 = fem.Constant(msh, 1.0), fem.Constant(msh, -1.0), fem.Constant(msh, 0.0)
    k = fem.Constant(msh, dt)

    def momentum(test):
        dudt = (a0 * u + a1 * u_n + a2 * u_nm1) / k
        return (rho * ufl.inner(dudt, test) + rho * ufl.inner(ufl.grad(u) * u, test)
                + mu * ufl.inner(ufl.grad(u), ufl.grad(test)) - p * ufl.div(test)) * ufl.dx

    F = momentum(v) - q * ufl.div(u) * ufl.dx
    problem = dolfinx.fem.petsc.NonlinearProblem(F, w, bcs)
    solver = newton_mumps(problem, 1e-8, 1e-10)

    # Reaction forces: the momentum residual tested with e_x / e_y on the cylinder's dofs.
    force_forms = []
    for comp in (0, 1):
        force_forms.append(fem.form(momentum(cylinder_unit_velocity(W, V, comp))))
    pts = np.array([[0.15, 0.2, 0.0], [0.25, 0.2, 0.0]])
    tree = geometry.BoundingBoxTree(msh, 2)
    coll = geometry.compute_colliding_cells(msh, geometry.compute_collisions(tree, pts), pts)
    cells_at = [coll.links(i)[:1] for i in range(2)]
    s = 2.0 / (rho * 1.0**2 * 0.1)  # mean inflow velocity 1 m/s, D = 0.1 m

    t0 = time.perf_counter()
    n_steps = int(round(t_end / dt))
    n_newton = 0
    with open(out, "w") as fo:
        fo.write("t,cd,cl,dp\n")
        for n in range(1, n_steps + 1):
            t = n * dt
            if n == 2:
                a0.value, a1.value, a2.value = 1.5, -2.0, 0.5
            inflow.interpolate(lambda y, f=ramp(t): np.vstack(
                (4 * u_max * f * y[1] * (H - y[1]) / H**2, 0 * y[0])))
            # predictor: extrapolation from the last two steps
            w.x.array[:] = 2 * w_n.x.array - w_nm1.x.array if n > 1 else w_n.x.array
            its, ok = solver.solve(w)
            n_newton += its
            assert ok
            cd, cl = (-s * fem.assemble_scalar(f) for f in force_forms)
            ph = w.sub(1).collapse()
            dp = ph.eval(pts[0], cells_at[0])[0] - ph.eval(pts[1], cells_at[1])[0]
            fo.write(f"{t:.8f},{cd:.10f},{cl:.10f},{dp:.10f}\n")
            w_nm1.x.array[:] = w_n.x.array
            w_n.x.array[:] = w.x.array
    print(f"cells {n_cells} dofs {W.dofmap.index_map.size_global * W.dofmap.index_map_bs} "
          f"steps {n_steps} newton {n_newton} wall {time.perf_counter() - t0:.1f} s")


if __name__ == "__main__":
    main(sys.argv[1], float(sys.argv[2]), float(sys.argv[3]), sys.argv[4],
         int(sys.argv[5]) if len(sys.argv) > 5 else 2)
