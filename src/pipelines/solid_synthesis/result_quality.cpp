#include "pipelines/solid_synthesis/result_quality.hpp"

#include "core/error.hpp"
#include "img/colour_histogram.hpp"
#include "par/gather_to_root.hpp"
#include "pipelines/solid_synthesis/slab_colours.hpp"
#include "pipelines/solid_synthesis/synthesis_metrics.hpp"

#include <mpi.h>

#include <span>
#include <vector>

namespace texsim::pipelines::solid_synthesis {
double slab_neighbourhood_error(const par::Comm& comm, const CoordinateSlab& slab,
                                const std::array<int, 3>& dims, const AppearanceLevel& finest,
                                const vol::ChannelGrid& exemplar_colours, int stride) {
  TEXSIM_VERIFY(stride > 0, "neighbourhood_error: stride must be positive, got " << stride);
  const int reach = finest.window / 2;
  TEXSIM_VERIFY(reach <= kSlabHalo, "a " << finest.window << "-voxel appearance window reaches "
                                         << "past the slab's " << kSlabHalo << "-plane halo");
  // On every rank, so that an exemplar without a scale fails them all alike.
  const double spread = appearance_spread(finest.features);
  const int dimension = finest.features.channels();
  const int n = slab.size();
  const PlaneRange planes = reported_planes(comm, slab, dims[2]);
  // Sample planes one at a time: the colours of the planes a sample's neighbourhood covers.
  std::vector<float> queries;
  const int first = (planes.begin + stride - 1) / stride * stride;
  for (int k = first; k < planes.end; k += stride) {
    const vol::ChannelGrid around =
        coloured_planes(slab, exemplar_colours, n, n, k - reach, 2 * reach + 1);
    for (int j = 0; j < dims[1]; j += stride)
      for (int i = 0; i < dims[0]; i += stride) {
        queries.resize(queries.size() + static_cast<std::size_t>(dimension));
        project_neighbourhood(finest, around, i, j, reach,
                              std::span<float>(queries).last(static_cast<std::size_t>(dimension)));
      }
  }
  const std::vector<double> mine = nearest_appearance_distances(queries, finest.features);
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
