#include "pipelines/fem_rd/geometry_smoother.hpp"

#include "geom/curvature_tensor.hpp"

#include <mpi.h>

namespace texsim::pipelines::fem_rd {
namespace {

/// Replaces the halo's tensors by their owners' (computed on complete neighbourhoods).
void update_halo(const geom::DistributedMesh& mesh, std::vector<Eigen::Matrix3d>& tensors) {
  std::vector<double> flat(9 * tensors.size());
  for (std::size_t v = 0; v < tensors.size(); ++v)
    std::copy(tensors[v].data(), tensors[v].data() + 9, flat.begin() + std::ptrdiff_t(9 * v));
  mesh.update_halo(flat, 9);
  for (std::size_t v = 0; v < tensors.size(); ++v)
    std::copy(flat.begin() + std::ptrdiff_t(9 * v), flat.begin() + std::ptrdiff_t(9 * v + 9),
              tensors[v].data());
}

} // namespace

GeometrySmoother::GeometrySmoother(const par::Comm& comm, geom::DistributedMesh& mesh,
                                   const SmoothingOptions& options)
    : comm_(comm), mesh_(mesh), options_(options),
      diffusion_(comm, mesh, options.lumped_mass, options.rtol) {}

geom::DensityWeights GeometrySmoother::density_weights() const {
  // Normalised by the mean lumped area of the whole surface: owned parts summed over the ranks.
  const auto part = geom::lumped_area_sum(mesh_.mesh(), mesh_.topology(), mesh_.owned_count());
  double local[2] = {part.area, double(part.vertices)}, total[2];
  MPI_Allreduce(local, total, 2, MPI_DOUBLE, MPI_SUM, comm_.raw);
  std::vector<double> density(mesh_.mesh().positions.size(), 1.0);
  if (total[1] > 0 && total[0] > 0)
    density = geom::mesh_density_function(mesh_.mesh(), mesh_.topology(), total[0] / total[1]);
  mesh_.update_halo(density);
  return geom::density_weights(density, options_.mu);
}

void GeometrySmoother::step() {
  // Coefficients at step n, exact at owned vertices (their neighbourhoods lie in the local
  // mesh), the ghosts' from their owners.
  const auto& surface = mesh_.mesh();
  std::vector<Eigen::Matrix3d> tensors(surface.positions.size(), Eigen::Matrix3d::Identity());
  if (!options_.isotropic) {
    tensors = geom::feature_diffusion_tensors(geom::principal_curvatures(surface, mesh_.topology()),
                                              options_.feature);
    update_halo(mesh_, tensors);
  }
  diffusion_.assemble(density_weights(), tensors, options_.dt);

  std::vector<double> moved(3 * std::size_t(mesh_.owned_count()));
  std::vector<double> coordinate(mesh_.owned_count());
  for (int axis = 0; axis < 3; ++axis) {
    for (std::int32_t v = 0; v < mesh_.owned_count(); ++v)
      coordinate[v] = surface.positions[v][axis];
    diffusion_.advance(coordinate);
    for (std::int32_t v = 0; v < mesh_.owned_count(); ++v)
      moved[3 * v + axis] = coordinate[v];
  }
  mesh_.set_owned_positions(moved);
}

void GeometrySmoother::smooth_function(std::span<double> owned) {
  std::vector<double> values(mesh_.mesh().positions.size());
  std::copy(owned.begin(), owned.end(), values.begin());
  mesh_.update_halo(values);
  auto tensors = geom::function_diffusion_tensors(mesh_.mesh(), mesh_.topology(), values,
                                                  options_.function_lambda);
  update_halo(mesh_, tensors);
  diffusion_.assemble(density_weights(), tensors, options_.dt);
  diffusion_.advance(owned);
}

} // namespace texsim::pipelines::fem_rd
