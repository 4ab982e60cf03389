# SPDX-License-Identifier: GPL-3.0-or-later
# Shared set-up of the Schaefer-Turek runs with dolfinx (dolfinx_2d1.py, dolfinx_2d2.py): the mesh
# file written by gf_fem_bench_st_2d1, the P2-P1 space on it, the channel's boundaries and a
# Newton solver with MUMPS LU.
import numpy as np
import ufl
from mpi4py import MPI
from petsc4py import PETSc

import dolfinx.nls.petsc
from dolfinx import cpp, fem
from dolfinx import mesh as dmesh

H = 0.41  # channel height, m


def read_mesh(path):
    """Nodes (n x 2) and quadratic triangles (n x 6, grainflow's node order) of a mesh file."""
    with open(path) as f:
        n_nodes, n_cells = map(int, f.readline().split())
        data = np.loadtxt(f, max_rows=n_nodes)
    cells = np.loadtxt(path, skiprows=1 + n_nodes, dtype=np.int64).reshape(n_cells, 6)
    return data[:, :2].copy(), cells


def taylor_hood(x, cells, degree=2):
    """The curved P2 mesh and its Taylor-Hood space W (velocity of `degree`, pressure of
    degree - 1: P2-P1 by default, P3-P2 for a higher-order cross-check) with the collapsed
    velocity space V."""
    cells = cells[:, cpp.io.perm_vtk(dmesh.CellType.triangle, 6)]
    domain = ufl.Mesh(ufl.VectorElement("Lagrange", "triangle", 2))
    msh = dmesh.create_mesh(MPI.COMM_WORLD, cells, x, domain)
    Pu = ufl.VectorElement("Lagrange", msh.ufl_cell(), degree)
    Pp = ufl.FiniteElement("Lagrange", msh.ufl_cell(), degree - 1)
    W = fem.FunctionSpace(msh, Pu * Pp)
    V, _ = W.sub(0).collapse()
    return msh, W, V


def on_cyl(p):
    # P3 edge dofs lie on the quadratic (not the exact) circle: a few 1e-9 off it; the nearest
    # interior dofs are ~1e-3 away.
    return np.abs(np.hypot(p[0] - 0.2, p[1] - 0.2) - 0.05) < 1e-6


def on_walls(p):
    return np.logical_or(np.isclose(p[1], 0.0), np.isclose(p[1], H))


def on_inflow(p):
    return np.isclose(p[0], 0.0)


def velocity_bcs(W, V, inflow):
    """No slip on the walls and the cylinder, `inflow` (a function on V) on the inflow edge."""
    zero = fem.Function(V)
    bcs = []
    for marker, g in ((on_walls, zero), (on_cyl, zero), (on_inflow, inflow)):
        dofs = fem.locate_dofs_geometrical((W.sub(0), V), marker)
        bcs.append(fem.dirichletbc(g, dofs, W.sub(0)))
    return bcs


def newton_mumps(problem, rtol, atol):
    """Newton on the increments, a new MUMPS LU per iteration."""
    solver = dolfinx.nls.petsc.NewtonSolver(MPI.COMM_WORLD, problem)
    solver.convergence_criterion = "incremental"
    solver.rtol = rtol
    solver.atol = atol
    solver.max_it = 25
    ksp = solver.krylov_solver
    opts = PETSc.Options()
    pre = ksp.getOptionsPrefix()
    opts[f"{pre}ksp_type"] = "preonly"
    opts[f"{pre}pc_type"] = "lu"
    opts[f"{pre}pc_factor_mat_solver_type"] = "mumps"
    ksp.setFromOptions()
    return solver


def cylinder_unit_velocity(W, V, comp):
    """A velocity that is e_comp at the cylinder's dofs and 0 elsewhere: the momentum residual
    tested with it is minus the fluid's force component on the cylinder (reaction force)."""
    vd = fem.Function(W)
    dofs = fem.locate_dofs_geometrical((W.sub(0).sub(comp), V.sub(comp).collapse()[0]), on_cyl)
    vd.x.array[dofs[0]] = 1.0
    return ufl.split(vd)[0]
