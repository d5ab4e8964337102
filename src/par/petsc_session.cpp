#include "par/petsc_session.hpp"

#include <cblas.h>

#include <sstream>

namespace texsim::par {

PetscSession::PetscSession(int& argc, char**& argv) {
  // PETSc's own error handler prints a traceback on every rank; texsim reports errors itself.
  TEXSIM_PETSC_CALL(PetscInitialize(&argc, &argv, nullptr, nullptr));
  TEXSIM_PETSC_CALL(PetscPushErrorHandler(PetscReturnErrorHandler, nullptr));
  // PETSc's vector dot products and updates go through OpenBLAS, which splits them over its
  // threads (OMP_NUM_THREADS by default): the rounding, and so every solver result, would depend
  // on the thread count. One BLAS thread keeps a run's bytes the same for any OMP_NUM_THREADS;
  // our own loops carry the threads.
  openblas_set_num_threads(1);
}

PetscSession::~PetscSession() {
  PetscFinalize();
}

void throw_petsc_error(PetscErrorCode code, const char* expression, const char* file, int line) {
  const char* text = nullptr;
  PetscErrorMessage(code, &text, nullptr);
  std::ostringstream out;
  out << "PETSc call failed: " << expression << ": " << (text ? text : "unknown error") << " (code "
      << code << ") [" << file << ":" << line << "]";
  throw Error(out.str());
}

} // namespace texsim::par
