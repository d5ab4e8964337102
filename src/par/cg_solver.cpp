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

CgSolver::CgSolver(const Comm& comm, double rtol, Preconditioner preconditioner) {
  TEXSIM_PETSC_CALL(KSPCreate(comm.raw, ksp_.address()));
  TEXSIM_PETSC_CALL(KSPSetType(ksp_, KSPCG));
  TEXSIM_PETSC_CALL(KSPSetTolerances(ksp_, rtol, 1e-50, PETSC_DEFAULT, 10000));
  TEXSIM_PETSC_CALL(KSPSetInitialGuessNonzero(ksp_, PETSC_TRUE));
  PC pc = nullptr;
  TEXSIM_PETSC_CALL(KSPGetPC(ksp_, &pc));
  if (preconditioner == Preconditioner::kJacobi) {
    TEXSIM_PETSC_CALL(PCSetType(pc, PCJACOBI));
  } else {
    TEXSIM_PETSC_CALL(PCSetType(pc, PCBJACOBI));
    // The block solvers read their options when the PC is set up.
    default_option("-sub_pc_type", "icc");
    default_option("-sub_pc_factor_mat_ordering_type", "rcm");
  }
  TEXSIM_PETSC_CALL(KSPSetFromOptions(ksp_));
}

void CgSolver::solve(Mat A, Vec b, Vec x) {
  TEXSIM_PETSC_CALL(KSPSetOperators(ksp_, A, A));
  TEXSIM_PETSC_CALL(KSPSolve(ksp_, b, x));
  KSPConvergedReason reason;
  TEXSIM_PETSC_CALL(KSPGetConvergedReason(ksp_, &reason));
  if (reason < 0) {
    // The reason is the same on every rank, so every rank throws and main() exits cleanly.
    Error error(std::string("linear solve diverged: ") + KSPConvergedReasons[reason] +
                " (try a smaller time step or other -ksp_type/-pc_type options)");
    error.mark_on_all_ranks();
    throw error;
  }
  PetscInt iterations = 0;
  TEXSIM_PETSC_CALL(KSPGetIterationNumber(ksp_, &iterations));
  TEXSIM_PETSC_CALL(KSPGetResidualNorm(ksp_, &stats_.last_residual));
  ++stats_.solves;
  stats_.iterations += iterations;
  stats_.max_iterations = std::max(stats_.max_iterations, int(iterations));
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
