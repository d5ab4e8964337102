#include "par/petsc_session.hpp"

#include <sstream>

namespace texsim::par {

PetscSession::PetscSession(int& argc, char**& argv) {
  // PETSc's own error handler prints a traceback on every rank; texsim reports errors itself.
  TEXSIM_PETSC_CALL(PetscInitialize(&argc, &argv, nullptr, nullptr));
  TEXSIM_PETSC_CALL(PetscPushErrorHandler(PetscReturnErrorHandler, nullptr));
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
