#include "pipelines/fem_rd/anisotropic_diffusion_step.hpp"

#include "par/petsc_session.hpp"

#include <algorithm>

namespace texsim::pipelines::fem_rd {

AnisotropicDiffusionStep::AnisotropicDiffusionStep(const par::Comm& comm,
                                                   const geom::DistributedMesh& mesh,
                                                   bool lumped_mass, double rtol)
    : mesh_(mesh), lumped_mass_(lumped_mass), assembler_(mesh), solver_(comm, rtol) {
  system_ = assembler_.create_matrix(comm);
  weighted_mass_ = assembler_.create_matrix(comm);
  TEXSIM_PETSC_CALL(MatCreateVecs(system_, field_.address(), rhs_.address()));
}

void AnisotropicDiffusionStep::assemble(const geom::DensityWeights& weights,
                                        std::span<const Eigen::Matrix3d> tensors, double dt) {
  assembler_.update_geometry();
  const std::int32_t local_count = mesh_.local_count();
  std::vector<double> mass_weight(local_count), stiffness_tensor(9 * std::size_t(local_count));
  for (std::int32_t local = 0; local < local_count; ++local) {
    mass_weight[local] = weights.mass[local];
    const Eigen::Matrix3d tensor = weights.stiffness[local] * tensors[local];
    for (int k = 0; k < 9; ++k)
      stiffness_tensor[9 * local + k] = tensor(k / 3, k % 3);
  }
  const auto mass = assembler_.mass_values(mass_weight, lumped_mass_);
  auto system = assembler_.stiffness_values(stiffness_tensor);
  for (std::size_t k = 0; k < system.size(); ++k)
    system[k] = mass[k] + dt * system[k];
  assembler_.set_values(weighted_mass_, mass);
  assembler_.set_values(system_, system);
}

void AnisotropicDiffusionStep::advance(std::span<double> owned) {
  double* values = nullptr;
  TEXSIM_PETSC_CALL(VecGetArray(field_, &values));
  std::copy(owned.begin(), owned.end(), values);
  TEXSIM_PETSC_CALL(VecRestoreArray(field_, &values));
  TEXSIM_PETSC_CALL(MatMult(weighted_mass_, field_, rhs_));
  solver_.solve(system_, rhs_, field_);
  const double* solved = nullptr;
  TEXSIM_PETSC_CALL(VecGetArrayRead(field_, &solved));
  std::copy(solved, solved + owned.size(), owned.begin());
  TEXSIM_PETSC_CALL(VecRestoreArrayRead(field_, &solved));
}

} // namespace texsim::pipelines::fem_rd
