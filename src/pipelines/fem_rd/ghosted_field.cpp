#include "pipelines/fem_rd/ghosted_field.hpp"

#include "core/error.hpp"
#include "par/petsc_session.hpp"

#include <algorithm>

namespace texsim::pipelines::fem_rd {

GhostedField::GhostedField(const par::Comm& comm, const geom::DistributedMesh& mesh)
    : local_(mesh.local_count(), 0.0) {
  const std::vector<PetscInt> ghosts(mesh.ghosts().begin(), mesh.ghosts().end());
  TEXSIM_PETSC_CALL(VecCreateGhost(comm.raw, mesh.owned_count(), PETSC_DETERMINE,
                                   PetscInt(ghosts.size()), ghosts.data(), vec_.address()));
}

void GhostedField::set_owned(std::span<const double> owned) {
  PetscInt size = 0;
  TEXSIM_PETSC_CALL(VecGetLocalSize(vec_, &size));
  TEXSIM_VERIFY(PetscInt(owned.size()) == size,
                "set_owned: " << owned.size() << " values for " << size << " owned vertices");
  double* values = nullptr;
  TEXSIM_PETSC_CALL(VecGetArray(vec_, &values));
  std::copy(owned.begin(), owned.end(), values);
  TEXSIM_PETSC_CALL(VecRestoreArray(vec_, &values));
  update_ghosts();
}

void GhostedField::update_ghosts() {
  TEXSIM_PETSC_CALL(VecGhostUpdateBegin(vec_, INSERT_VALUES, SCATTER_FORWARD));
  TEXSIM_PETSC_CALL(VecGhostUpdateEnd(vec_, INSERT_VALUES, SCATTER_FORWARD));
  Vec local_form = nullptr;
  TEXSIM_PETSC_CALL(VecGhostGetLocalForm(vec_, &local_form));
  const double* values = nullptr;
  TEXSIM_PETSC_CALL(VecGetArrayRead(local_form, &values));
  std::copy(values, values + local_.size(), local_.begin());
  TEXSIM_PETSC_CALL(VecRestoreArrayRead(local_form, &values));
  TEXSIM_PETSC_CALL(VecGhostRestoreLocalForm(vec_, &local_form));
}

} // namespace texsim::pipelines::fem_rd
