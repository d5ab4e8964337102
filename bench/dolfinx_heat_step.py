# Sample run: OMP_NUM_THREADS=1 mpirun --allow-run-as-root -n 2 /usr/bin/python3 bench/dolfinx_heat_step.py --level 7
"""DOLFINx reference timings for one backward Euler heat step on the unit icosphere.

This is the FEM peer that texsim's P1 surface solver is measured against. It builds the same
level-L icosphere as texsim (geom/icosphere.cpp), sets up P1 Lagrange and times, as medians over
--repeats runs with every timed region between MPI barriers:

  compile_s             JIT compilation of the bilinear and linear forms (once, cold cache
                        unless --jit-cache-dir points at a warm one);
  assemble_matrix_s     A = M + tau*K assembled into an existing PETSc matrix;
  assemble_rhs_s        b = M u^n assembled as the linear form u^n*v*dx;
  pc_setup_s            preconditioner set-up after A changed;
  solve_s               KSP CG solve with the preconditioner already set up;
  matmult_s             one y = A x, the memory bandwidth reference;
  step_s                rhs assembly + solve with A and the preconditioner reused;
  step_with_assembly_s  matrix assembly + rhs assembly + preconditioner set-up + solve.

It then checks the answer: u^0 = (3z^2 - 1) + 1, and after one step the l = 2 amplitude must shrink
by about 1/(1 + 6 tau). One JSON object is printed on rank 0's stdout; all logging goes to stderr.
Unrecognised command line arguments go into PETSc's options database before the solver reads it
(-ksp_monitor, -pc_gamg_threshold 0.02, ...; their output lands on stdout, so the JSON is then no
longer alone there). Options PETSc reads only at start-up, such as -log_view, must be given through
the PETSC_OPTIONS environment variable.

Needs Debian 12's python3-dolfinx, run with /usr/bin/python3 (not a pyenv interpreter).
"""

import argparse
import json
import logging
import os
import shutil
import statistics
import sys
import tempfile
import time

import numpy as np
import ufl
from mpi4py import MPI
from petsc4py import PETSc

import dolfinx
import dolfinx.fem.petsc
from dolfinx import fem

SPHERICAL_HARMONIC_DEGREE = 2
INITIAL_CONSTANT = 1.0


def log(comm, message):
    """Writes message to stderr on rank 0 only."""
    if comm.rank == 0:
        print(message, file=sys.stderr, flush=True)


def icosahedron():
    """Returns the 12 vertices and 20 triangles of texsim's icosahedron (not yet on the sphere)."""
    phi = (1.0 + np.sqrt(5.0)) / 2.0
    positions = np.array(
        [[-1, phi, 0], [1, phi, 0], [-1, -phi, 0], [1, -phi, 0],
         [0, -1, phi], [0, 1, phi], [0, -1, -phi], [0, 1, -phi],
         [phi, 0, -1], [phi, 0, 1], [-phi, 0, -1], [-phi, 0, 1]], dtype=np.float64)
    triangles = np.array(
        [[0, 11, 5], [0, 5, 1], [0, 1, 7], [0, 7, 10], [0, 10, 11],
         [1, 5, 9], [5, 11, 4], [11, 10, 2], [10, 7, 6], [7, 1, 8],
         [3, 9, 4], [3, 4, 2], [3, 2, 6], [3, 6, 8], [3, 8, 9],
         [4, 9, 5], [2, 4, 11], [6, 2, 10], [8, 6, 7], [9, 8, 1]], dtype=np.int64)
    return positions, triangles


def split_at_midpoints(positions, triangles):
    """Splits every triangle into four at its edge midpoints, shared between neighbours.

    Numbering follows texsim: edges are the unique sorted vertex pairs in lexicographic order, and
    the midpoint of edge e becomes vertex num_vertices + e. Side i of a triangle is the one opposite
    corner i.
    """
    num_vertices = positions.shape[0]
    first = triangles[:, [1, 2, 0]]
    second = triangles[:, [2, 0, 1]]
    keys = np.minimum(first, second) * num_vertices + np.maximum(first, second)
    edge_keys, side_to_edge = np.unique(keys.ravel(), return_inverse=True)
    edge_lo, edge_hi = np.divmod(edge_keys, num_vertices)
    midpoints = 0.5 * (positions[edge_lo] + positions[edge_hi])
    mid = num_vertices + side_to_edge.reshape(triangles.shape)
    fine = np.stack(
        [np.stack([triangles[:, 0], mid[:, 2], mid[:, 1]], axis=1),
         np.stack([triangles[:, 1], mid[:, 0], mid[:, 2]], axis=1),
         np.stack([triangles[:, 2], mid[:, 1], mid[:, 0]], axis=1),
         np.stack([mid[:, 0], mid[:, 1], mid[:, 2]], axis=1)], axis=1)
    return np.concatenate([positions, midpoints]), fine.reshape(-1, 3)


def icosphere(level):
    """Returns (positions, triangles) of texsim's unit icosphere refined `level` times.

    Every refinement projects all vertices back onto the unit sphere, as geom::icosphere does.
    """
    positions, triangles = icosahedron()
    for _ in range(level):
        positions, triangles = split_at_midpoints(positions, triangles)
        positions /= np.linalg.norm(positions, axis=1)[:, None]
    positions /= np.linalg.norm(positions, axis=1)[:, None]
    return positions, triangles


def create_sphere_mesh(comm, level):
    """Builds the icosphere on rank 0 and lets DOLFINx partition it over comm. Collective."""
    if comm.rank == 0:
        positions, triangles = icosphere(level)
    else:
        positions = np.empty((0, 3), dtype=np.float64)
        triangles = np.empty((0, 3), dtype=np.int64)
    cell = ufl.Cell("triangle", geometric_dimension=3)
    domain = ufl.Mesh(ufl.VectorElement("Lagrange", cell, 1, dim=3))
    return dolfinx.mesh.create_mesh(comm, triangles, positions, domain)


def barrier_timed(comm, action):
    """Runs action() between two barriers and returns (seconds on this rank, its result)."""
    comm.Barrier()
    start = time.perf_counter()
    result = action()
    comm.Barrier()
    return time.perf_counter() - start, result


def median_time(comm, action, repeats, prepare=None):
    """Median over `repeats` of barrier_timed(action); prepare() runs untimed before each one."""
    times = []
    for _ in range(repeats):
        if prepare is not None:
            prepare()
        seconds, _ = barrier_timed(comm, action)
        times.append(seconds)
    return statistics.median(times)


def shared_jit_cache_dir(comm, requested):
    """Returns (cache directory, whether it is a fresh one to delete). Collective.

    Without a requested directory, rank 0 makes a fresh one so compile_s measures a cold compile.
    """
    if requested:
        return requested, False
    path = tempfile.mkdtemp(prefix="dolfinx_heat_jit_") if comm.rank == 0 else None
    return comm.bcast(path, root=0), True


def configure_solver(comm, A, pc_type, rtol):
    """Creates a CG KSP on A with the chosen preconditioner, then applies command line options."""
    options = PETSc.Options()
    if pc_type == "bjacobi" and not options.hasName("sub_pc_type"):
        options["sub_pc_type"] = "icc"
    ksp = PETSc.KSP().create(comm)
    ksp.setOperators(A)
    ksp.setType(PETSc.KSP.Type.CG)
    ksp.getPC().setType(pc_type)
    ksp.setTolerances(rtol=rtol, atol=0.0, max_it=10000)
    ksp.setFromOptions()
    return ksp


class HeatStep:
    """Forms, matrix, vectors and solver of one backward Euler step (M + tau K) u = M u^n."""

    def __init__(self, mesh, tau, jit_params):
        self.mesh = mesh
        self.comm = mesh.comm
        self.space = fem.FunctionSpace(mesh, ("Lagrange", 1), jit_params=jit_params)
        self.u_old = fem.Function(self.space)
        self.u_new = fem.Function(self.space)
        self.tau = tau
        u = ufl.TrialFunction(self.space)
        v = ufl.TestFunction(self.space)
        self.bilinear = u * v * ufl.dx + tau * ufl.inner(ufl.grad(u), ufl.grad(v)) * ufl.dx
        self.linear = self.u_old * v * ufl.dx
        self.jit_params = jit_params

    def compile(self):
        """JIT-compiles both forms (collective)."""
        self.a = fem.form(self.bilinear, jit_params=self.jit_params)
        self.L = fem.form(self.linear, jit_params=self.jit_params)

    def allocate(self, pc_type, rtol):
        """Creates the matrix (sparsity), the rhs vector and the solver."""
        self.A = fem.petsc.create_matrix(self.a)
        self.b = fem.petsc.create_vector(self.L)
        self.assemble_matrix()
        self.ksp = configure_solver(self.comm, self.A, pc_type, rtol)

    def assemble_matrix(self):
        """Assembles A = M + tau K into the existing matrix."""
        self.A.zeroEntries()
        fem.petsc.assemble_matrix(self.A, self.a)
        self.A.assemble()

    def assemble_rhs(self):
        """Assembles b = M u^n into the existing vector, owned entries complete."""
        with self.b.localForm() as local:
            local.set(0.0)
        fem.petsc.assemble_vector(self.b, self.L)
        self.b.ghostUpdate(addv=PETSc.InsertMode.ADD, mode=PETSc.ScatterMode.REVERSE)

    def setup_preconditioner(self):
        """Rebuilds the preconditioner for the current values of A, including the block
        factorisations (ICC) that PETSc would otherwise defer to the next solve."""
        self.ksp.setOperators(self.A)
        self.ksp.setUp()
        self.ksp.setUpOnBlocks()

    def solve(self):
        """Solves A u^{n+1} = b from a zero initial guess; returns the CG iteration count."""
        self.ksp.solve(self.b, self.u_new.vector)
        reason = self.ksp.getConvergedReason()
        if reason <= 0:
            raise RuntimeError(f"KSP did not converge (reason {reason})")
        self.u_new.x.scatter_forward()
        return self.ksp.getIterationNumber()

    def step(self):
        """Right-hand side assembly + solve, matrix and preconditioner reused."""
        self.assemble_rhs()
        return self.solve()

    def step_with_assembly(self):
        """Matrix reassembly + right-hand side assembly + preconditioner set-up + solve."""
        self.assemble_matrix()
        self.setup_preconditioner()
        return self.step()


def integrate(comm, integrand):
    """Global integral of a UFL expression over the mesh. Collective."""
    return comm.allreduce(fem.assemble_scalar(fem.form(integrand)), op=MPI.SUM)


def harmonic_amplitude_ratio(heat, harmonic):
    """(u^{n+1} - mean, Y)_L2 / (u^n - mean, Y)_L2: the measured decay factor of mode Y."""
    comm = heat.comm
    area = integrate(comm, fem.Constant(heat.mesh, 1.0) * ufl.dx)
    harmonic_integral = integrate(comm, harmonic * ufl.dx)

    def projection(u):
        mean = integrate(comm, u * ufl.dx) / area
        return integrate(comm, u * harmonic * ufl.dx) - mean * harmonic_integral

    return projection(heat.u_new) / projection(heat.u_old)


def initial_condition(x):
    """u^0 = (3 z^2 - 1) + 1 at points x (shape (3, n))."""
    return 3.0 * x[2] ** 2 - 1.0 + INITIAL_CONSTANT


def spherical_harmonic(x):
    """The degree-2 zonal spherical harmonic 3 z^2 - 1 (unnormalised)."""
    return 3.0 * x[2] ** 2 - 1.0


def run(args, comm):
    """Builds the problem, runs all timings and the decay check; returns the result dictionary."""
    seconds, mesh = barrier_timed(comm, lambda: create_sphere_mesh(comm, args.level))
    num_vertices = mesh.topology.index_map(0).size_global
    num_triangles = mesh.topology.index_map(2).size_global
    log(comm, f"mesh: level {args.level}, {num_vertices} vertices, {num_triangles} triangles, "
              f"{comm.size} ranks, built and distributed in {seconds:.3f} s")

    cache_dir, fresh_cache = shared_jit_cache_dir(comm, args.jit_cache_dir)
    try:
        heat = HeatStep(mesh, args.tau, {"cache_dir": cache_dir})
        compile_s, _ = barrier_timed(comm, heat.compile)
    finally:
        comm.Barrier()
        if fresh_cache and comm.rank == 0:
            shutil.rmtree(cache_dir, ignore_errors=True)
    log(comm, f"form compilation: {compile_s:.3f} s ({'cold' if fresh_cache else 'given'} cache)")

    heat.u_old.interpolate(initial_condition)
    heat.u_old.x.scatter_forward()
    heat.allocate(args.pc, args.rtol)
    matrix_info = heat.A.getInfo(PETSc.Mat.InfoType.GLOBAL_SUM)

    assemble_matrix_s = median_time(comm, heat.assemble_matrix, args.repeats)
    assemble_rhs_s = median_time(comm, heat.assemble_rhs, args.repeats)
    pc_setup_s = median_time(comm, heat.setup_preconditioner, args.repeats,
                             prepare=heat.assemble_matrix)
    cg_iters = heat.solve()  # untimed warm-up; the timed solves repeat exactly this one
    solve_s = median_time(comm, heat.solve, args.repeats)
    x = heat.A.createVecRight()
    x.set(1.0)
    y = heat.A.createVecLeft()
    matmult_s = median_time(comm, lambda: heat.A.mult(x, y), args.repeats)
    step_s = median_time(comm, heat.step, args.repeats)
    step_with_assembly_s = median_time(comm, heat.step_with_assembly, args.repeats)
    log(comm, f"assemble A {assemble_matrix_s:.4f} s, rhs {assemble_rhs_s:.4f} s, "
              f"pc setup {pc_setup_s:.4f} s, solve {solve_s:.4f} s ({cg_iters} CG its), "
              f"matmult {matmult_s:.5f} s, step {step_s:.4f} s, "
              f"step with assembly {step_with_assembly_s:.4f} s")

    harmonic = fem.Function(heat.space)
    harmonic.interpolate(spherical_harmonic)
    heat.step()
    decay_factor = harmonic_amplitude_ratio(heat, harmonic)
    ell = SPHERICAL_HARMONIC_DEGREE
    decay_expected = 1.0 / (1.0 + args.tau * ell * (ell + 1))
    log(comm, f"l=2 decay factor {decay_factor:.8f}, expected {decay_expected:.8f} "
              f"(relative difference {abs(decay_factor / decay_expected - 1.0):.2e})")

    return {
        "vertices": int(num_vertices),
        "triangles": int(num_triangles),
        "ranks": comm.size,
        "omp_num_threads": os.environ.get("OMP_NUM_THREADS", "unset"),
        "tau": args.tau,
        "pc": args.pc,
        "rtol": args.rtol,
        "repeats": args.repeats,
        "matrix_nnz": int(matrix_info["nz_used"]),
        "compile_s": compile_s,
        "assemble_matrix_s": assemble_matrix_s,
        "assemble_rhs_s": assemble_rhs_s,
        "pc_setup_s": pc_setup_s,
        "solve_s": solve_s,
        "cg_iters": int(cg_iters),
        "matmult_s": matmult_s,
        "step_s": step_s,
        "step_with_assembly_s": step_with_assembly_s,
        "decay_factor": decay_factor,
        "decay_expected": decay_expected,
        "dolfinx_version": dolfinx.__version__,
        "petsc_version": ".".join(str(part) for part in PETSc.Sys.getVersion()),
    }


def parse_args(argv):
    """Returns (benchmark options, leftover arguments meant for PETSc)."""
    parser = argparse.ArgumentParser(
        description=__doc__.split("\n\n")[0],
        epilog="Other arguments go to PETSc's options database (e.g. -pc_gamg_threshold 0.02); "
               "start-up options such as -log_view need PETSC_OPTIONS.")
    parser.add_argument("--level", type=int, default=7,
                        help="icosphere refinement level (7: 163,842 vertices; default 7)")
    parser.add_argument("--tau", type=float, default=1e-3, help="time step (default 1e-3)")
    parser.add_argument("--pc", choices=["gamg", "bjacobi", "jacobi"], default="gamg",
                        help="CG preconditioner; bjacobi uses ICC(0) blocks (default gamg)")
    parser.add_argument("--rtol", type=float, default=1e-8,
                        help="CG relative residual tolerance (default 1e-8)")
    parser.add_argument("--repeats", type=int, default=5,
                        help="timed repetitions, medians are reported (default 5)")
    parser.add_argument("--jit-cache-dir", default=None,
                        help="DOLFINx JIT cache to use (default: a fresh one, so compile_s "
                             "is a cold compile)")
    args, petsc_args = parser.parse_known_args(argv)
    if not 0 <= args.level <= 10:
        parser.error(f"--level {args.level} outside [0, 10]")
    if args.tau <= 0.0 or args.rtol <= 0.0 or args.repeats < 1:
        parser.error("--tau and --rtol must be positive and --repeats at least 1")
    return args, petsc_args


def main():
    args, petsc_args = parse_args(sys.argv[1:])
    logging.disable(logging.INFO)
    if petsc_args:
        PETSc.Options().insertString(" ".join(petsc_args))
    comm = MPI.COMM_WORLD
    result = run(args, comm)
    if comm.rank == 0:
        print(json.dumps(result))


if __name__ == "__main__":
    main()
