#pragma once
/// Owning handles for PETSc objects: the object is destroyed with its handle, so early returns and
/// exceptions do not leak. Usage:
///   par::PetscMat A;  TEXSIM_PETSC_CALL(MatCreate(comm, A.address()));  MatMult(A, x, y);
#include <petscksp.h>
#include <petscmat.h>
#include <petscvec.h>

#include <utility>

namespace texsim::par {

template <class Object, PetscErrorCode (*Destroy)(Object*)> class PetscHandle {
public:
  PetscHandle() = default;
  ~PetscHandle() { reset(); }
  PetscHandle(const PetscHandle&) = delete;
  PetscHandle& operator=(const PetscHandle&) = delete;
  PetscHandle(PetscHandle&& other) noexcept : object_(std::exchange(other.object_, nullptr)) {}
  PetscHandle& operator=(PetscHandle&& other) noexcept {
    if (this != &other) {
      reset();
      object_ = std::exchange(other.object_, nullptr);
    }
    return *this;
  }

  /// For PETSc's create functions; the handle must be empty.
  Object* address() { return &object_; }
  operator Object() const { return object_; }
  Object get() const { return object_; }
  explicit operator bool() const { return object_ != nullptr; }

  /// Destroys the object (if any). Collective on the object's communicator.
  void reset() {
    if (object_)
      Destroy(&object_);
    object_ = nullptr;
  }

private:
  Object object_ = nullptr;
};

using PetscVec = PetscHandle<Vec, VecDestroy>;
using PetscMat = PetscHandle<Mat, MatDestroy>;
using PetscKsp = PetscHandle<KSP, KSPDestroy>;
using PetscIs = PetscHandle<IS, ISDestroy>;
using PetscMatPartitioning = PetscHandle<MatPartitioning, MatPartitioningDestroy>;

} // namespace texsim::par
