#include "pipelines/fem_rd/pattern_regions.hpp"

#include "geom/graph_regions.hpp"

#include <mpi.h>

#include <algorithm>
#include <limits>
#include <numeric>
#include <vector>

namespace texsim::pipelines::fem_rd {

RegionCount count_regions_above_mean(const geom::DistributedMesh& mesh,
                                     std::span<const double> owned) {
  const auto& comm = mesh.comm();
  RegionCount count;
  double local_sum[2] = {std::accumulate(owned.begin(), owned.end(), 0.0), double(owned.size())};
  double sum[2];
  MPI_Allreduce(local_sum, sum, 2, MPI_DOUBLE, MPI_SUM, comm.raw);
  if (sum[1] == 0)
    return count;
  count.threshold = sum[0] / sum[1];

  // Above the mean: owned vertices and ghosts (the outer halo stays out of the graph).
  const std::size_t local_vertices = mesh.mesh().positions.size();
  std::vector<double> values(local_vertices, 0.0);
  std::copy(owned.begin(), owned.end(), values.begin());
  mesh.update_halo(values);
  std::vector<char> above(local_vertices, 0);
  for (std::int32_t v = 0; v < mesh.local_count(); ++v)
    above[v] = values[v] > count.threshold;
  const auto components = geom::label_regions(mesh.topology().vertex_neighbors(), above);
  const std::int32_t component_count =
      1 + std::max(-1, *std::max_element(components.begin(), components.end()));

  // Each local component takes the smallest label any of its vertices carries; the ghosts then
  // take their owners' labels. Labels only fall, so this ends.
  constexpr double kNone = std::numeric_limits<double>::infinity();
  std::vector<double> label(local_vertices, kNone);
  for (std::int32_t v = 0; v < mesh.local_count(); ++v)
    if (above[v])
      label[v] = double(mesh.global_index(v));
  for (int changed = 1; changed;) {
    std::vector<double> smallest(std::size_t(component_count), kNone);
    for (std::int32_t v = 0; v < mesh.local_count(); ++v)
      if (components[v] >= 0)
        smallest[components[v]] = std::min(smallest[components[v]], label[v]);
    int mine = 0;
    for (std::int32_t v = 0; v < mesh.local_count(); ++v)
      if (components[v] >= 0 && smallest[components[v]] < label[v]) {
        mine |= v < mesh.owned_count();
        label[v] = smallest[components[v]];
      }
    mesh.update_halo(label);
    MPI_Allreduce(&mine, &changed, 1, MPI_INT, MPI_LOR, comm.raw);
  }

  std::int64_t local_counts[2] = {0, 0}, counts[2];
  for (std::int32_t v = 0; v < mesh.owned_count(); ++v)
    if (above[v]) {
      ++local_counts[1];
      local_counts[0] += label[v] == double(mesh.global_index(v));
    }
  MPI_Allreduce(local_counts, counts, 2, MPI_INT64_T, MPI_SUM, comm.raw);
  count.regions = int(counts[0]);
  count.mean_vertices = count.regions ? double(counts[1]) / count.regions : 0.0;
  return count;
}

} // namespace texsim::pipelines::fem_rd
