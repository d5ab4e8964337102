#pragma once
/// MPI and PETSc initialised once per process, finalised on destruction, plus the PETSc call check.
#include "core/error.hpp"

#include <petscsys.h>

namespace texsim::par {

/// Initialises MPI (through PETSc) and PETSc with the command line, so PETSc options given there
/// (-ksp_type cg ...) reach PETSc's options database. One per process, in main(). Collective.
class PetscSession {
public:
  PetscSession(int& argc, char**& argv);
  ~PetscSession();
  PetscSession(const PetscSession&) = delete;
  PetscSession& operator=(const PetscSession&) = delete;
};

/// Throws texsim::Error with PETSc's message when a PETSc call fails.
void throw_petsc_error(PetscErrorCode code, const char* expression, const char* file, int line);

} // namespace texsim::par

/// Wraps every PETSc call: TEXSIM_PETSC_CALL(KSPSolve(ksp, b, x));
#define TEXSIM_PETSC_CALL(expression)                                                              \
  do {                                                                                             \
    const PetscErrorCode texsim_petsc_code_ = (expression);                                        \
    if (texsim_petsc_code_ != 0)                                                                   \
      ::texsim::par::throw_petsc_error(texsim_petsc_code_, #expression, __FILE__, __LINE__);       \
  } while (0)
