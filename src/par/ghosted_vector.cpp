#include "par/ghosted_vector.hpp"

#include "core/error.hpp"
#include "par/petsc_session.hpp"

#include <algorithm>

namespace texsim::par {

GhostedVector::GhostedVector(const Comm& comm, std::int64_t owned_count,
                             std::span<const std::int32_t> ghosts, int block_size)
    : block_size_(block_size), owned_size_(std::size_t(block_size) * std::size_t(owned_count)),
      local_(owned_size_ + std::size_t(block_size) * ghosts.size(), 0.0) {
  const std::vector<PetscInt> ghost_blocks(ghosts.begin(), ghosts.end());
  TEXSIM_PETSC_CALL(VecCreateGhostBlockWithArray(
      comm.raw, block_size, PetscInt(owned_size_), PETSC_DETERMINE, PetscInt(ghost_blocks.size()),
      ghost_blocks.data(), local_.data(), vec_.address()));
}

void GhostedVector::set_owned(std::span<const double> owned_values) {
  TEXSIM_VERIFY(owned_values.size() == owned_size_, "set_owned: " << owned_values.size()
                                                                  << " values for " << owned_size_
                                                                  << " owned entries");
  std::copy(owned_values.begin(), owned_values.end(), local_.begin());
  update_ghosts();
}

void GhostedVector::update_ghosts() {
  // The owned values may have been written in place: a get/restore pair (no copy: the array is
  // ours) tells PETSc the vector changed, or it would keep serving cached norms of old values.
  double* values = nullptr;
  TEXSIM_PETSC_CALL(VecGetArray(vec_, &values));
  TEXSIM_PETSC_CALL(VecRestoreArray(vec_, &values));
  TEXSIM_PETSC_CALL(VecGhostUpdateBegin(vec_, INSERT_VALUES, SCATTER_FORWARD));
  TEXSIM_PETSC_CALL(VecGhostUpdateEnd(vec_, INSERT_VALUES, SCATTER_FORWARD));
}

} // namespace texsim::par
