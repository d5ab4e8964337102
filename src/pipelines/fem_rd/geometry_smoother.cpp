#include "pipelines/fem_rd/geometry_smoother.hpp"

#include "geom/curvature_tensor.hpp"
#include "par/petsc_session.hpp"

namespace texsim::pipelines::fem_rd {

GeometrySmoother::GeometrySmoother(const par::Comm& comm, geom::DistributedMesh& mesh,
                                   const SmoothingOptions& options)
    : comm_(comm), mesh_(mesh), options_(options), assembler_(mesh), solver_(comm, options.rtol) {
  system_ = assembler_.create_matrix(comm);
  weighted_mass_ = assembler_.create_matrix(comm);
  TEXSIM_PETSC_CALL(MatCreateVecs(system_, coordinate_.address(), rhs_.address()));
}

void GeometrySmoother::step() {
  // Coefficients at step n, on the whole surface (every rank holds it), then per local vertex.
  const auto& surface = mesh_.mesh();
  const auto weights =
      geom::density_weights(geom::mesh_density_function(surface, mesh_.topology()), options_.mu);
  std::vector<Eigen::Matrix3d> tensors;
  if (!options_.isotropic)
    tensors = geom::feature_diffusion_tensors(geom::principal_curvatures(surface, mesh_.topology()),
                                              options_.feature);
  const std::int32_t local_count = mesh_.local_count();
  std::vector<double> mass_weight(local_count), stiffness_tensor(9 * std::size_t(local_count));
  for (std::int32_t local = 0; local < local_count; ++local) {
    const std::int32_t g = mesh_.global_index(local);
    mass_weight[local] = weights.mass[g];
    const Eigen::Matrix3d tensor =
        weights.stiffness[g] * (options_.isotropic ? Eigen::Matrix3d::Identity() : tensors[g]);
    for (int k = 0; k < 9; ++k)
      stiffness_tensor[9 * local + k] = tensor(k / 3, k % 3);
  }
  const auto mass = assembler_.mass_values(mass_weight, options_.lumped_mass);
  auto system = assembler_.stiffness_values(stiffness_tensor);
  for (std::size_t k = 0; k < system.size(); ++k)
    system[k] = mass[k] + options_.dt * system[k];
  assembler_.set_values(weighted_mass_, mass);
  assembler_.set_values(system_, system);

  const std::int32_t begin = mesh_.owned_begin();
  std::vector<double> moved(3 * std::size_t(mesh_.owned_count()));
  for (int axis = 0; axis < 3; ++axis) {
    double* values = nullptr;
    TEXSIM_PETSC_CALL(VecGetArray(coordinate_, &values));
    for (std::int32_t v = 0; v < mesh_.owned_count(); ++v)
      values[v] = surface.positions[begin + v][axis];
    TEXSIM_PETSC_CALL(VecRestoreArray(coordinate_, &values));
    TEXSIM_PETSC_CALL(MatMult(weighted_mass_, coordinate_, rhs_));
    solver_.solve(system_, rhs_, coordinate_);
    const double* solved = nullptr;
    TEXSIM_PETSC_CALL(VecGetArrayRead(coordinate_, &solved));
    for (std::int32_t v = 0; v < mesh_.owned_count(); ++v)
      moved[3 * v + axis] = solved[v];
    TEXSIM_PETSC_CALL(VecRestoreArrayRead(coordinate_, &solved));
  }
  const auto all = mesh_.gather(comm_, moved, 3);
  std::vector<geom::Vec3> positions(mesh_.global_count());
  for (std::size_t v = 0; v < positions.size(); ++v)
    positions[v] = geom::Vec3(all[3 * v], all[3 * v + 1], all[3 * v + 2]);
  mesh_.set_positions(positions);
}

} // namespace texsim::pipelines::fem_rd
