#!/usr/bin/python3
"""A FEM host: GetFEM assembles a linear-elastic block pressed onto a rigid plane with Coulomb
friction, and frix solves the frictional contact of every load step.

The block [0, Lx] x [0, Ly] x [0, Lz] (trilinear hexahedra) has its top face held by a rigid
plate that moves down by `press` and then sideways by up to `shift` over the load steps (the
normal load, then a growing tangential one). Its bottom nodes touch a rigid plane tilted by
`tilt` about the y axis, so part of the bottom stays open, part sticks and part slides.

frix gets the problem in the global form, on the dofs that are not held by the plate:
    M v = H r + f,  u = H^T v + w
M the stiffness K_ff, v the displacement, f = -K_fd u_plate, H one column per contact
direction (the plane's normal at each bottom node, then two tangents), w the initial gap
(normal) and 0 (tangents), r the contact forces in each node's frame. The load steps change
f only, so one frix.Solver (the persistent solver: M's factorisation and the reduction are
kept) solves them all. GetFEM's friction law is "static" (the slip is the total tangential
displacement), as this form is: each step is the same problem with another f.

    block_on_plane.py                                  frix, 4 load steps, 10x10x4 elements
    block_on_plane.py --getfem                         and GetFEM's own solver, compared
    block_on_plane.py --mesh 40 40 12 --getfem --oneshot --fclib block.hdf5
                                                       60,516 dofs, 1,681 contacts; timed;
                                                       the last step written as FCLIB

--fclib writes the last step's problem (global form) with a solution: GetFEM's when it ran,
else frix's. examples/plugin_host solves such a file through frix's dlopen table.
GetFEM sets OpenBLAS to one thread when it loads, for the whole process: here frix's dense
kernels run on one thread too.
Needs Debian's python3-getfem and the frix package (PYTHONPATH=build/python in the tree).
"""
import argparse
import sys
import time
from types import SimpleNamespace

import numpy as np
import scipy.sparse as sp

import frix

try:
    import getfem as gf
except ImportError:  # the caller decides what a missing GetFEM means (the tests skip)
    gf = None

OPEN, STICK, SLIDE = 0, 1, 2
STATE_NAMES = ("open", "stick", "slide")
_BOTTOM, _TOP = 1, 2


def _scipy_csc(spmat):
    """A GetFEM sparse matrix as a scipy CSC matrix."""
    colptr, rowind = spmat.csc_ind()
    return sp.csc_matrix((spmat.csc_val(), rowind, colptr), shape=tuple(spmat.size()))


class Block:
    """The elastic block on the tilted plane, assembled by GetFEM; the global problem frix
    solves (M, H, w, mu, and f of a load) and GetFEM's own frictional contact solve of it."""

    def __init__(self, nx, ny, nz, size=(1.0, 1.0, 0.3), young=1e3, poisson=0.3, friction=0.3,
                 tilt=0.01):
        if gf is None:
            raise RuntimeError("GetFEM is not installed (Debian's python3-getfem)")
        self.young, self.poisson, self.friction, self.tilt = young, poisson, friction, tilt
        self.mesh = gf.Mesh("cartesian", *(np.linspace(0.0, length, cells + 1)
                                           for length, cells in zip(size, (nx, ny, nz))))
        faces = self.mesh.outer_faces()
        normals = self.mesh.normal_of_faces(faces)
        self.mesh.set_region(_BOTTOM, faces[:, np.nonzero(normals[2] < -0.99)[0]])
        self.mesh.set_region(_TOP, faces[:, np.nonzero(normals[2] > 0.99)[0]])
        self.mfu = gf.MeshFem(self.mesh, 3)
        self.mfu.set_classical_fem(1)
        self.mim = gf.MeshIm(self.mesh, gf.Integ("IM_GAUSS_PARALLELEPIPED(3,2)"))
        self.lame = (young * poisson / ((1 + poisson) * (1 - 2 * poisson)),
                     young / (2 * (1 + poisson)))
        mfd = gf.MeshFem(self.mesh, 1)
        mfd.set_classical_fem(1)
        K = _scipy_csc(gf.asm_linear_elasticity(self.mim, self.mfu, mfd,
                                                np.full(mfd.nbdof(), self.lame[0]),
                                                np.full(mfd.nbdof(), self.lame[1])))
        n = self.mfu.nbdof()
        self.plate = self.mfu.basic_dof_on_region(_TOP)
        self.free = np.setdiff1d(np.arange(n), self.plate)
        rows = K[self.free]
        self.M = rows[:, self.free].tocsc()
        self._K_plate = rows[:, self.plate].tocsc()
        self._K = K

        # The contact nodes in GetFEM's order (its brick's multipliers follow it): the bottom
        # face's dofs, three per node.
        self.contact_dofs = self.mfu.basic_dof_on_region(_BOTTOM).reshape(-1, 3)
        nc = self.contact_dofs.shape[0]
        where = self.mfu.basic_dof_nodes(self.contact_dofs[:, 0])
        c = np.sqrt(1.0 + tilt * tilt)
        # The plane z = -tilt x; its normal into the block, then two tangents.
        self.frame = np.array([[tilt, 0.0, 1.0], [1.0, 0.0, -tilt], [0.0, c, 0.0]]) / c
        position = np.full(n, -1, dtype=np.int64)
        position[self.free] = np.arange(self.free.size)
        rows = position[self.contact_dofs]                      # nc x 3 (x, y, z of each node)
        self.H = sp.csc_matrix((np.tile(self.frame.reshape(-1), nc),
                                (np.repeat(rows, 3, axis=0).reshape(-1),
                                 np.repeat(np.arange(3 * nc), 3))),
                               shape=(self.free.size, 3 * nc))
        self.w = np.zeros(3 * nc)
        self.w[0::3] = (where[2] + tilt * where[0]) / c         # the gap to the plane
        self.mu = np.full(nc, friction)
        self._model = None

    @property
    def contacts(self):
        return self.contact_dofs.shape[0]

    @property
    def dofs(self):
        return self.free.size

    def plate_displacement(self, load):
        """The plate's displacement (press, shift) on the top face's dofs."""
        press, shift = load
        u = np.zeros(self.plate.size)
        u[0::3], u[2::3] = shift, -press
        return u

    def f(self, load):
        """f of a load: the forces the plate's displacement puts on the free dofs."""
        return -(self._K_plate @ self.plate_displacement(load))

    def problem(self, load):
        """The frix global problem of one load."""
        return frix.Problem.from_global(self.M, self.H, self.f(load), self.w, self.mu)

    def contact_velocity(self, v):
        """u = H^T v + w: per contact the gap after displacement, then the slip."""
        return self.H.T @ v + self.w

    def _getfem_model(self):
        if self._model is None:
            md = gf.Model("real")
            md.add_fem_variable("u", self.mfu)
            md.add_initialized_data("lambda", [self.lame[0]])
            md.add_initialized_data("mu", [self.lame[1]])
            md.add_isotropic_linearized_elasticity_brick(self.mim, "u", "lambda", "mu")
            md.add_initialized_data("plate", [0.0, 0.0, 0.0])
            md.add_Dirichlet_condition_with_simplification("u", _TOP, "plate")
            md.add_variable("lambda_n", self.contacts)
            md.add_variable("lambda_t", 2 * self.contacts)
            md.add_initialized_data("r", [self.young])              # augmentation, about E
            md.add_initialized_data("friction", [self.friction])
            c = np.sqrt(1.0 + self.tilt * self.tilt)
            obstacle = f"(z + {self.tilt!r} * x) / {c!r}"          # signed distance to the plane
            # Alart-Curnier's non-symmetric augmented Lagrangian (version 1).
            md.add_nodal_contact_with_rigid_obstacle_brick(
                self.mim, "u", "lambda_n", "lambda_t", "r", "friction", _BOTTOM, obstacle, 1)
            self._model = md
        return self._model

    def getfem_solve(self, load, max_res=1e-12, max_iter=100):
        """GetFEM's own solve of a load (its Newton on the nodal contact brick, MUMPS for the
        linear systems), from its previous step's answer. Returns (v, r, Newton iterations,
        CPU seconds, wall seconds): v on the free dofs, r in frix's frames (from K u at the
        contact nodes, which is the contact force GetFEM's multipliers put there)."""
        md = self._getfem_model()
        press, shift = load
        md.set_variable("plate", [shift, 0.0, -press])
        cpu, wall = time.process_time(), time.perf_counter()
        iterations, converged = md.solve("max_res", max_res, "max_iter", max_iter,
                                         "lsolver", "mumps")
        cpu, wall = time.process_time() - cpu, time.perf_counter() - wall
        if not converged:
            raise RuntimeError(f"GetFEM's Newton did not converge in {max_iter} iterations")
        u = md.variable("u")
        force = (self._K @ u)[self.contact_dofs]                # nc x 3, in x, y, z
        r = (force @ self.frame.T).reshape(-1)
        return u[self.free], r, int(iterations), cpu, wall

    def states(self, r, v, rel=1e-7):
        """Each contact's state (OPEN, STICK, SLIDE) from r and v: open where r_N is below
        rel times the largest r_N; of the closed ones, slide where the slip is above rel times
        the largest displacement."""
        r = np.asarray(r).reshape(-1, 3)
        u = self.contact_velocity(v).reshape(-1, 3)
        slip = np.linalg.norm(u[:, 1:], axis=1)
        state = np.where(slip > rel * np.abs(v).max(), SLIDE, STICK)
        state[r[:, 0] <= rel * r[:, 0].max()] = OPEN
        return state


def loads(steps, press=0.006, shift=0.002):
    """The load path: the plate pressed down by `press`, then shifted by up to `shift`."""
    return [(press, shift * k / max(steps - 1, 1)) for k in range(steps)]


def _counts(state):
    return ", ".join(f"{np.count_nonzero(state == s)} {name}" for s, name in enumerate(STATE_NAMES))


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--mesh", nargs=3, type=int, default=(10, 10, 4), metavar=("NX", "NY", "NZ"),
                        help="elements along x, y, z (default 10 10 4)")
    parser.add_argument("--steps", type=int, default=4, help="load steps (default 4)")
    parser.add_argument("--tol", type=float, default=1e-8, help="frix's tolerance (default 1e-8)")
    parser.add_argument("--solver", default="auto", help="frix's solver (default auto)")
    parser.add_argument("--getfem", action="store_true",
                        help="also solve each step with GetFEM's contact brick and compare")
    parser.add_argument("--oneshot", action="store_true",
                        help="also solve each step with a one-shot frix.solve, for its time")
    parser.add_argument("--fclib", metavar="PATH", help="write the last step as an FCLIB file")
    args = parser.parse_args(argv)
    if gf is None:
        print("block_on_plane: GetFEM is not installed (Debian's python3-getfem)", file=sys.stderr)
        return 77
    if args.steps < 1:
        parser.error("--steps must be at least 1")

    gf.util_trace_level(0)
    start = time.perf_counter()
    block = Block(*args.mesh)
    print(f"block {args.mesh[0]}x{args.mesh[1]}x{args.mesh[2]}: {block.dofs} dofs, "
          f"{block.contacts} contacts, M {block.M.nnz} nonzeros; GetFEM assembly "
          f"{time.perf_counter() - start:.2f} s")
    path = loads(args.steps)
    problem = block.problem(path[0])
    solver = frix.Solver(problem, solver=args.solver, tol=args.tol)
    ok = True  # every step converged and, with --getfem, agreed with GetFEM's
    for k, load in enumerate(path):
        f = block.f(load)
        solver.update(f=f)
        cpu = time.process_time()
        res = solver.solve()
        cpu = time.process_time() - cpu
        ok = ok and res.converged
        state = block.states(res.r, res.v)
        print(f"step {k} (press {load[0]:g}, shift {load[1]:g}): frix persistent {res.status}, "
              f"error {res.error:.1e}, {res.time:.3f} s (CPU {cpu:.3f} s); {_counts(state)}")
        step_problem = block.problem(load) if args.oneshot or args.getfem else None
        if args.oneshot:
            cpu = time.process_time()
            one = frix.solve(step_problem, solver=args.solver, tol=args.tol)
            cpu = time.process_time() - cpu
            print(f"    frix one-shot {one.status}, error {one.error:.1e}, "
                  f"{one.time:.3f} s (CPU {cpu:.3f} s)")
        answer = SimpleNamespace(r=res.r, u=res.u, v=res.v)
        if args.getfem:
            v, r, iterations, cpu, wall = block.getfem_solve(load)
            theirs = frix.measure(step_problem, r, v)
            same = np.array_equal(block.states(r, v), state)
            dv = np.abs(res.v - v).max() / np.abs(v).max()
            dr = np.abs(res.r - r).max() / np.abs(r).max()
            print(f"    GetFEM {iterations} Newton iterations, {wall:.3f} s (CPU {cpu:.3f} s), "
                  f"its answer's error by frix's measure {theirs['error_scaled']:.1e}; "
                  f"same states: {'yes' if same else 'NO'}; |v - v_getfem| / |v_getfem| {dv:.1e}, "
                  f"|r - r_getfem| / |r_getfem| {dr:.1e}")
            ok = ok and same and dv <= 1e-6 and dr <= 1e-5
            answer = SimpleNamespace(r=r, u=block.contact_velocity(v), v=v)
    if args.fclib:
        last = block.problem(path[-1])
        mesh = "x".join(str(m) for m in args.mesh)
        last.save(args.fclib, solution=answer, title=f"GetFEM elastic block {mesh} on a tilted plane",
                  description=(f"Linear-elastic block (E {block.young:g}, nu {block.poisson:g}) of "
                               f"{mesh} trilinear hexahedra assembled by GetFEM, pressed by "
                               f"{path[-1][0]:g} and shifted by {path[-1][1]:g} onto a rigid plane "
                               f"tilted by {block.tilt:g}, Coulomb friction {block.friction:g}; "
                               f"solution: {'GetFEM' if args.getfem else 'frix'}"))
        print(f"wrote {args.fclib}")
    solver.close()
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
