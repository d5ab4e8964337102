#include "pipelines/fem_rd/geometry_smoother.hpp"

#include "geom/curvature_tensor.hpp"

namespace texsim::pipelines::fem_rd {

GeometrySmoother::GeometrySmoother(const par::Comm& comm, geom::DistributedMesh& mesh,
                                   const SmoothingOptions& options)
    : comm_(comm), mesh_(mesh), options_(options),
      diffusion_(comm, mesh, options.lumped_mass, options.rtol) {}

geom::DensityWeights GeometrySmoother::density_weights() const {
  return geom::density_weights(geom::mesh_density_function(mesh_.mesh(), mesh_.topology()),
                               options_.mu);
}

void GeometrySmoother::step() {
  // Coefficients at step n on the whole surface (every rank holds it).
  const auto& surface = mesh_.mesh();
  std::vector<Eigen::Matrix3d> tensors(mesh_.global_count(), Eigen::Matrix3d::Identity());
  if (!options_.isotropic)
    tensors = geom::feature_diffusion_tensors(geom::principal_curvatures(surface, mesh_.topology()),
                                              options_.feature);
  diffusion_.assemble(density_weights(), tensors, options_.dt);

  const std::int32_t begin = mesh_.owned_begin();
  std::vector<double> moved(3 * std::size_t(mesh_.owned_count()));
  std::vector<double> coordinate(mesh_.owned_count());
  for (int axis = 0; axis < 3; ++axis) {
    for (std::int32_t v = 0; v < mesh_.owned_count(); ++v)
      coordinate[v] = surface.positions[begin + v][axis];
    diffusion_.advance(coordinate);
    for (std::int32_t v = 0; v < mesh_.owned_count(); ++v)
      moved[3 * v + axis] = coordinate[v];
  }
  const auto all = mesh_.gather(comm_, moved, 3);
  std::vector<geom::Vec3> positions(mesh_.global_count());
  for (std::size_t v = 0; v < positions.size(); ++v)
    positions[v] = geom::Vec3(all[3 * v], all[3 * v + 1], all[3 * v + 2]);
  mesh_.set_positions(positions);
}

void GeometrySmoother::smooth_function(std::span<double> owned) {
  const auto values = mesh_.gather(comm_, owned);
  const auto tensors = geom::function_diffusion_tensors(mesh_.mesh(), mesh_.topology(), values,
                                                        options_.function_lambda);
  diffusion_.assemble(density_weights(), tensors, options_.dt);
  diffusion_.advance(owned);
}

} // namespace texsim::pipelines::fem_rd
