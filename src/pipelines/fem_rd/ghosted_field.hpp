#pragma once
/// A scalar field on the vertices of a DistributedMesh as a PETSc ghosted vector: the global form
/// is what KSP solves into; the local form holds owned values then ghost values, in the mesh's
/// local numbering, which is what element loops read.
#include "geom/distributed_mesh.hpp"
#include "par/comm.hpp"
#include "par/petsc_handle.hpp"

#include <span>
#include <vector>

namespace texsim::pipelines::fem_rd {

class GhostedField {
public:
  /// Zero field. Collective.
  GhostedField(const par::Comm& comm, const geom::DistributedMesh& mesh);

  /// The global (MPI) vector: owned entries only.
  Vec vec() const { return vec_; }

  /// Owned values followed by ghosts (valid after update_ghosts()). Not collective.
  std::span<const double> local() const { return local_; }

  /// Sets the owned values (owned_count of them) and refreshes ghosts. Collective.
  void set_owned(std::span<const double> owned);

  /// Copies owned values from the vector into local() and fetches ghost values. Collective.
  void update_ghosts();

private:
  par::PetscVec vec_;
  std::vector<double> local_;
};

} // namespace texsim::pipelines::fem_rd
