#pragma once
/// Preconditioned conjugate gradients through PETSc KSP with texsim's defaults set in code
/// (CG, the preconditioner the caller picks, relative tolerance from the config) and then
/// KSPSetFromOptions, so -ksp_* / -pc_* options on the command line or under `petsc:` override
/// them. Counts iterations and keeps the last residual for the run summary.
#include "par/comm.hpp"
#include "par/petsc_handle.hpp"

#include <string>

namespace texsim::par {

struct SolveStats {
  int solves = 0;
  long long iterations = 0; ///< summed over solves
  int max_iterations = 0;
  double last_residual = 0; ///< preconditioned residual norm of the last solve

  double mean_iterations() const { return solves ? double(iterations) / solves : 0.0; }
};

/// Default preconditioners, chosen by measurement (bench/fem_step_bench.cpp, level-7 sphere):
/// block Jacobi with ICC(0) in reverse Cuthill-McKee order per rank for stiffness-dominated
/// systems (heat step: 23 iterations instead of 34 in natural order), point Jacobi for
/// mass-dominated systems whose matrix changes every step (the RD step: no factorization to
/// rebuild, 2x faster than ICC). On raw scans, whose slivers make the same systems badly
/// conditioned, algebraic multigrid: PETSc's smoothed aggregation (GAMG) or hypre's BoomerAMG
/// (docs/fem_rd.md has the measured iterations).
enum class Preconditioner { kBlockJacobiIcc, kJacobi, kGamg, kBoomerAmg };

/// "bjacobi+icc", "jacobi", "gamg", "boomeramg".
const char* preconditioner_name(Preconditioner preconditioner);

class CgSolver {
public:
  /// `rtol`: relative residual reduction. Collective.
  CgSolver(const Comm& comm, double rtol,
           Preconditioner preconditioner = Preconditioner::kBlockJacobiIcc);

  /// Solves A x = b with x's content as the initial guess. The preconditioner is rebuilt when
  /// A's values changed since the last solve. Throws texsim::Error naming PETSc's reason when
  /// the solve diverges. Collective.
  void solve(Mat A, Vec b, Vec x) { solve(A, A, b, x); }
  /// Like solve(A, b, x), with the preconditioner built from P instead of A: it is set up again
  /// only when P's values or pattern changed since the last solve, so an AMG hierarchy built from
  /// a fixed P is reused by every solve. Collective.
  void solve(Mat A, Mat P, Vec b, Vec x);
  /// Solves A x = b, preconditioned from A, but stops after `limit` iterations without throwing;
  /// true when it converged. Counts in stats() like solve(). Collective.
  bool solve_within(Mat A, Vec b, Vec x, int limit);

  const SolveStats& stats() const { return stats_; }
  /// "cg + bjacobi" (KSP and PC types in effect, after options).
  std::string description() const;

private:
  /// KSPSolve and bookkeeping; returns PETSc's reason.
  KSPConvergedReason run(Mat A, Mat P, Vec b, Vec x);

  PetscKsp ksp_;
  SolveStats stats_;
};

} // namespace texsim::par
