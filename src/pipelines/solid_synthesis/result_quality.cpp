#include "pipelines/solid_synthesis/result_quality.hpp"

#include "core/error.hpp"
#include "img/colour_histogram.hpp"
#include "par/gather_to_root.hpp"
#include "par/node_shared_array.hpp"
#include "pipelines/solid_synthesis/correction_stencil.hpp"
#include "pipelines/solid_synthesis/distinct_features.hpp"
#include "pipelines/solid_synthesis/slab_colours.hpp"
#include "pipelines/solid_synthesis/synthesis_metrics.hpp"

#include <mpi.h>

#include <Eigen/Core>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <span>
#include <vector>

namespace texsim::pipelines::solid_synthesis {
namespace {

/// The result's colour window around voxel p in the field's frame, `window`^3 voxels x fastest
/// into `out`: window offset delta (exemplar axes) lies at output point p + A^-1 delta, and is
/// read through the voxel q nearest to it (at most kSlabHalo away per axis) as the exemplar
/// colour at S[q] + delta - (A_p + A_q) / 2 (q - p), q's continuation of its patch (the
/// synthesis' prediction, make_stencil). A = I gives S[p + delta],
/// the plain window; an exactly warped copy of the exemplar gives the exemplar's own window.
void framed_window(const CoordinateSlab& slab, const LevelJacobians* jacobians,
                   const vol::ChannelGrid& exemplar_colours, int i, int j, int k, int window,
                   vol::ChannelGrid& out) {
  const int reach = window / 2;
  for (int dz = -reach; dz <= reach; ++dz)
    for (int dy = -reach; dy <= reach; ++dy)
      for (int dx = -reach; dx <= reach; ++dx) {
        Position position;
        if (jacobians) {
          const Eigen::Vector3f delta{float(dx), float(dy), float(dz)};
          const Eigen::Vector3f at = jacobians->a_inverse(i, j, k) * delta;
          const auto step = [](float v) {
            return std::clamp(static_cast<int>(std::floor(v + 0.5f)), -kSlabHalo, kSlabHalo);
          };
          const Eigen::Vector3i q(step(at.x()), step(at.y()), step(at.z()));
          const Eigen::Matrix3f mean =
              (jacobians->a(i, j, k) + jacobians->a_periodic(i + q.x(), j + q.y(), k + q.z())) *
              0.5f;
          const Eigen::Vector3f shift = delta - mean * q.cast<float>();
          position = slab.at(i + q.x(), j + q.y(), k + q.z()) + fixed_point(shift);
        } else {
          position = slab.at(i + dx, j + dy, k + dz);
        }
        const Coord c = position.voxel();
        const auto colour = exemplar_colours.voxel(exemplar_colours.periodic_index(c.x, c.y, c.z));
        std::copy(colour.begin(), colour.end(),
                  out.voxel(out.index(dx + reach, dy + reach, dz + reach)).begin());
      }
}

} // namespace

double slab_neighbourhood_error(const par::Comm& comm, const CoordinateSlab& slab,
                                const LevelJacobians* jacobians, const std::array<int, 3>& dims,
                                const AppearanceLevel& finest,
                                const vol::ChannelGrid& exemplar_colours, int stride) {
  TEXSIM_VERIFY(stride > 0, "neighbourhood_error: stride must be positive, got " << stride);
  const LevelLayout& layout = slab.layout();
  TEXSIM_VERIFY(!jacobians || layout.z_begin == layout.z_end ||
                    (jacobians->z_begin <= layout.z_begin - kSlabHalo &&
                     jacobians->z_end >= layout.z_end + kSlabHalo),
                "neighbourhood_error: the Jacobians must cover the owned planes and the halo");
  const int reach = finest.window / 2;
  TEXSIM_VERIFY(reach <= kSlabHalo, "a " << finest.window << "-voxel appearance window reaches "
                                         << "past the slab's " << kSlabHalo << "-plane halo");
  // On every rank, so that an exemplar without a scale fails them all alike.
  const double spread = appearance_spread(finest.features);
  const auto dimension = static_cast<std::size_t>(finest.features.channels());
  const PlaneRange planes = reported_planes(comm, slab, dims[2]);
  const int first = (planes.begin + stride - 1) / stride * stride;
  std::vector<std::array<int, 3>> samples;
  for (int k = first; k < planes.end; k += stride)
    for (int j = 0; j < dims[1]; j += stride)
      for (int i = 0; i < dims[0]; i += stride)
        samples.push_back({i, j, k});
  std::vector<float> queries(samples.size() * dimension);
#pragma omp parallel
  {
    vol::ChannelGrid window({finest.window, finest.window, finest.window},
                            exemplar_colours.channels());
#pragma omp for schedule(static)
    for (std::size_t s = 0; s < samples.size(); ++s) {
      const auto [i, j, k] = samples[s];
      framed_window(slab, jacobians, exemplar_colours, i, j, k, finest.window, window);
      project_neighbourhood(finest, window, reach, reach, reach,
                            std::span<float>(queries).subspan(s * dimension, dimension));
    }
  }
  // The exemplar's distinct vectors and their tree, once per node: every rank searches them.
  const auto node_layout = par::NodeLayout::make(comm);
  const vol::ChannelGrid distinct = distinct_feature_rows(finest.features, node_layout);
  const FeatureKdTree tree(distinct, node_layout);
  const std::vector<double> mine = nearest_appearance_distances(queries, distinct, tree);
  // Added on rank 0 in rank order, the volume's order: the same sum for any rank count.
  const std::vector<double> all = par::gather_to_root(comm, std::span<const double>(mine));
  double error = 0.0;
  if (comm.is_root()) {
    double sum = 0.0;
    for (const double distance : all)
      sum += distance;
    error = sum / static_cast<double>(all.size()) / spread;
  }
  MPI_Bcast(&error, 1, MPI_DOUBLE, 0, comm.raw);
  return error;
}

double slab_histogram_distance(const par::Comm& comm, const CoordinateSlab& slab,
                               const std::array<int, 3>& dims,
                               const vol::ChannelGrid& exemplar_colours) {
  const int channels = exemplar_colours.channels();
  img::ColourHistogram result(channels), exemplar(channels);
  exemplar.add(exemplar_colours.data());
  const PlaneRange planes = reported_planes(comm, slab, dims[2]);
  for (int k = planes.begin; k < planes.end; ++k)
    result.add(coloured_planes(slab, exemplar_colours, dims[0], dims[1], k, 1).data());
  MPI_Allreduce(MPI_IN_PLACE, result.counts().data(), static_cast<int>(result.counts().size()),
                MPI_INT64_T, MPI_SUM, comm.raw);
  return img::histogram_distance(result, exemplar);
}

} // namespace texsim::pipelines::solid_synthesis
