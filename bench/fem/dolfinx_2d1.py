#!/usr/bin/python3
# SPDX-License-Identifier: GPL-3.0-or-later
# Schaefer-Turek 2D-1 with dolfinx (Debian python3-dolfinx, P2-P1, Newton, MUMPS LU) on a mesh
# written by gf_fem_bench_st_2d1 (same nodes, same curved P2 cells), for the side-by-side timing.
# Usage: /usr/bin/python3 dolfinx_2d1.py mesh.txt   -> one CSV line on stdout
import sys
import time

import numpy as np
import ufl

import dolfinx.fem.petsc
from dolfinx import fem, geometry
from dolfinx import mesh as dmesh
from dolfinx_st import (H, cylinder_unit_velocity, newton_mumps, on_cyl, read_mesh, taylor_hood,
                        velocity_bcs)

CD_REF, CL_REF, DP_REF = 5.57953523384, 0.010618948146, 0.11752016697


def main(path):
    x, cells = read_mesh(path)
    n_cells = len(cells)
    t0 = time.perf_counter()
    msh, W, V = taylor_hood(x, cells)
    um = 0.3
    inflow = fem.Function(V)
    inflow.interpolate(lambda p: np.vstack((4 * um * p[1] * (H - p[1]) / H**2, 0 * p[0])))
    bcs = velocity_bcs(W, V, inflow)

    w = fem.Function(W)
    u, p = ufl.split(w)
    v, q = ufl.TestFunctions(W)
    rho, mu = 1.0, 1e-3
    F = (rho * ufl.inner(ufl.grad(u) * u, v) + mu * ufl.inner(ufl.grad(u), ufl.grad(v))
         - p * ufl.div(v) - q * ufl.div(u)) * ufl.dx
    problem = dolfinx.fem.petsc.NonlinearProblem(F, w, bcs)
    solver = newton_mumps(problem, 1e-10, 1e-12)
    t1 = time.perf_counter()
    n_it, converged = solver.solve(w)
    t2 = time.perf_counter()

    # Forces: reaction (residual with a test function = e_x / e_y on the cylinder) and surface stress.
    forces = []
    for comp in (0, 1):
        ud = cylinder_unit_velocity(W, V, comp)
        R = (rho * ufl.inner(ufl.grad(u) * u, ud) + mu * ufl.inner(ufl.grad(u), ufl.grad(ud))
             - p * ufl.div(ud)) * ufl.dx
        forces.append(-fem.assemble_scalar(fem.form(R)))
    facets = dmesh.locate_entities_boundary(msh, 1, on_cyl)
    tags = dmesh.meshtags(msh, 1, np.sort(facets), np.full(len(facets), 1, dtype=np.int32))
    ds = ufl.Measure("ds", domain=msh, subdomain_data=tags)
    n = -ufl.FacetNormal(msh)
    sigma = -p * ufl.Identity(2) + mu * (ufl.grad(u) + ufl.grad(u).T)
    fs = [fem.assemble_scalar(fem.form(ufl.dot(sigma, n)[i] * ds(1))) for i in (0, 1)]
    # pressure difference
    pts = np.array([[0.15, 0.2, 0.0], [0.25, 0.2, 0.0]])
    tree = geometry.BoundingBoxTree(msh, 2)
    coll = geometry.compute_colliding_cells(msh, geometry.compute_collisions(tree, pts), pts)
    ph = w.sub(1).collapse()
    pv = [ph.eval(pts[i], coll.links(i)[:1])[0] for i in range(2)]
    t3 = time.perf_counter()
    s = 2.0 / (rho * 0.2**2 * 0.1)
    cd, cl, dp = s * forces[0], s * forces[1], pv[0] - pv[1]
    print("cells,dofs,newton_it,converged,cd,cl,dp,cd_err,cl_err,dp_err,cd_stress,cl_stress,t_setup,t_solve,t_post,t_total")
    print(f"{n_cells},{W.dofmap.index_map.size_global * W.dofmap.index_map_bs},{n_it},{int(converged)},"
          f"{cd:.10f},{cl:.10f},{dp:.10f},{cd / CD_REF - 1:.3e},{cl / CL_REF - 1:.3e},{dp / DP_REF - 1:.3e},"
          f"{s * fs[0]:.10f},{s * fs[1]:.10f},{t1 - t0:.3f},{t2 - t1:.3f},{t3 - t2:.3f},{t2 - t0:.3f}")


if __name__ == "__main__":
    main(sys.argv[1])
