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
/// rebuild, 2x faster than ICC).
enum class Preconditioner { kBlockJacobiIcc, kJacobi };

class CgSolver {
public:
  /// `rtol`: relative residual reduction. Collective.
  CgSolver(const Comm& comm, double rtol,
           Preconditioner preconditioner = Preconditioner::kBlockJacobiIcc);

  /// Solves A x = b with x's content as the initial guess. The preconditioner is rebuilt when
  /// A's values changed since the last solve. Throws texsim::Error naming PETSc's reason when
  /// the solve diverges. Collective.
  void solve(Mat A, Vec b, Vec x);

  const SolveStats& stats() const { return stats_; }
  /// "cg + bjacobi" (KSP and PC types in effect, after options).
  std::string description() const;

private:
  PetscKsp ksp_;
  SolveStats stats_;
};

} // namespace texsim::par
