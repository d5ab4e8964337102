#include "par/cg_solver.hpp"

#include "core/error.hpp"
#include "par/petsc_session.hpp"

#include <algorithm>

namespace texsim::par {

namespace {
// Sets a PETSc option unless the user gave it on the command line or under `petsc:`.
void default_option(const char* name, const char* value) {
  PetscBool given = PETSC_FALSE;
  TEXSIM_PETSC_CALL(PetscOptionsHasName(nullptr, nullptr, name, &given));
  if (!given)
    TEXSIM_PETSC_CALL(PetscOptionsSetValue(nullptr, name, value));
}
} // namespace

const char* preconditioner_name(Preconditioner preconditioner) {
  switch (preconditioner) {
  case Preconditioner::kBlockJacobiIcc:
    return "bjacobi+icc";
  case Preconditioner::kJacobi:
    return "jacobi";
  case Preconditioner::kGamg:
    return "gamg";
  case Preconditioner::kBoomerAmg:
    return "boomeramg";
  }
  return "?";
}

CgSolver::CgSolver(const Comm& comm, double rtol, Preconditioner preconditioner) {
  TEXSIM_PETSC_CALL(KSPCreate(comm.raw, ksp_.address()));
  TEXSIM_PETSC_CALL(KSPSetType(ksp_, KSPCG));
  TEXSIM_PETSC_CALL(KSPSetTolerances(ksp_, rtol, 1e-50, PETSC_DEFAULT, 10000));
  TEXSIM_PETSC_CALL(KSPSetInitialGuessNonzero(ksp_, PETSC_TRUE));
  PC pc = nullptr;
  TEXSIM_PETSC_CALL(KSPGetPC(ksp_, &pc));
  switch (preconditioner) {
  case Preconditioner::kJacobi:
    TEXSIM_PETSC_CALL(PCSetType(pc, PCJACOBI));
    break;
  case Preconditioner::kBlockJacobiIcc:
    TEXSIM_PETSC_CALL(PCSetType(pc, PCBJACOBI));
    // The block solvers read their options when the PC is set up.
    default_option("-sub_pc_type", "icc");
    default_option("-sub_pc_factor_mat_ordering_type", "rcm");
    break;
  case Preconditioner::kGamg:
    TEXSIM_PETSC_CALL(PCSetType(pc, PCGAMG));
    break;
  case Preconditioner::kBoomerAmg:
    TEXSIM_PETSC_CALL(PCSetType(pc, PCHYPRE));
    TEXSIM_PETSC_CALL(PCHYPRESetType(pc, "boomeramg"));
    break;
  }
  TEXSIM_PETSC_CALL(KSPSetFromOptions(ksp_));
}

KSPConvergedReason CgSolver::run(Mat A, Mat P, Vec b, Vec x) {
  TEXSIM_PETSC_CALL(KSPSetOperators(ksp_, A, P));
  TEXSIM_PETSC_CALL(KSPSolve(ksp_, b, x));
  KSPConvergedReason reason;
  TEXSIM_PETSC_CALL(KSPGetConvergedReason(ksp_, &reason));
  PetscInt iterations = 0;
  TEXSIM_PETSC_CALL(KSPGetIterationNumber(ksp_, &iterations));
  TEXSIM_PETSC_CALL(KSPGetResidualNorm(ksp_, &stats_.last_residual));
  ++stats_.solves;
  stats_.iterations += iterations;
  stats_.max_iterations = std::max(stats_.max_iterations, int(iterations));
  return reason;
}

void CgSolver::solve(Mat A, Mat P, Vec b, Vec x) {
  const KSPConvergedReason reason = run(A, P, b, x);
  if (reason < 0) {
    // The reason is the same on every rank, so every rank throws and main() exits cleanly.
    Error error(std::string("linear solve diverged: ") + KSPConvergedReasons[reason] +
                " (try a smaller time step or other -ksp_type/-pc_type options)");
    error.mark_on_all_ranks();
    throw error;
  }
}

bool CgSolver::solve_within(Mat A, Vec b, Vec x, int limit) {
  PetscReal rtol = 0, abstol = 0, dtol = 0;
  PetscInt max_iterations = 0;
  TEXSIM_PETSC_CALL(KSPGetTolerances(ksp_, &rtol, &abstol, &dtol, &max_iterations));
  TEXSIM_PETSC_CALL(KSPSetTolerances(ksp_, rtol, abstol, dtol, limit));
  const KSPConvergedReason reason = run(A, A, b, x);
  TEXSIM_PETSC_CALL(KSPSetTolerances(ksp_, rtol, abstol, dtol, max_iterations));
  return reason > 0;
}

std::string CgSolver::description() const {
  KSPType ksp_type = nullptr;
  PCType pc_type = nullptr;
  PC pc = nullptr;
  TEXSIM_PETSC_CALL(KSPGetType(ksp_, &ksp_type));
  TEXSIM_PETSC_CALL(KSPGetPC(ksp_, &pc));
  TEXSIM_PETSC_CALL(PCGetType(pc, &pc_type));
  return std::string(ksp_type ? ksp_type : "?") + " + " + (pc_type ? pc_type : "?");
}

} // namespace texsim::par
