#pragma once
/// A distributed array as a PETSc ghosted vector: each rank owns a contiguous run of the global
/// index space and keeps read-only copies ("ghosts") of chosen entries owned by other ranks. The
/// global form is what KSP solves into; the local form holds owned values then ghost values, which
/// is what stencil and element loops read. Entries may be blocks of `block_size` values (e.g. all
/// species of one cell), kept together. Used by the FEM vertices and by Turk's cell graph alike.
/// The values live in one array this object owns and PETSc uses in place (no copies between
/// PETSc's storage and the local view), so an explicit stencil can write owned() directly and then
/// fetch ghosts.
#include "par/comm.hpp"
#include "par/petsc_handle.hpp"

#include <cstdint>
#include <span>
#include <vector>

namespace texsim::par {

class GhostedVector {
public:
  /// Zero vector with `owned_count` blocks on this rank and copies of the blocks whose global
  /// block indices are `ghosts` (owned elsewhere). Collective.
  GhostedVector(const Comm& comm, std::int64_t owned_count, std::span<const std::int32_t> ghosts,
                int block_size = 1);

  /// The global (MPI) vector: owned entries only.
  Vec vec() const { return vec_; }

  int block_size() const { return block_size_; }

  /// Owned values followed by ghosts (valid after update_ghosts()). Not collective.
  std::span<const double> local() const { return local_; }

  /// The owned values, writable in place; call update_ghosts() after writing. Not collective.
  std::span<double> owned() { return std::span(local_).first(owned_size_); }

  /// Sets the owned values (block_size * owned_count of them) and refreshes ghosts. Collective.
  void set_owned(std::span<const double> owned);

  /// Fetches the ghost values from their owners (after the owned values changed through owned()
  /// or through vec()). Collective.
  void update_ghosts();

  GhostedVector(const GhostedVector&) = delete;
  GhostedVector& operator=(const GhostedVector&) = delete;

private:
  int block_size_;
  std::size_t owned_size_;
  std::vector<double> local_; // declared before vec_: PETSc uses this storage until vec_ dies
  PetscVec vec_;
};

} // namespace texsim::par
