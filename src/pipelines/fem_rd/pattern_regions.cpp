#include "pipelines/fem_rd/pattern_regions.hpp"

#include "geom/distributed_regions.hpp"
#include "par/reproducible_sum.hpp"

#include <mpi.h>

#include <algorithm>
#include <vector>

namespace texsim::pipelines::fem_rd {

RegionCount count_regions_above_mean(const geom::DistributedMesh& mesh,
                                     std::span<const double> owned) {
  const auto& comm = mesh.comm();
  RegionCount count;
  std::int64_t vertices = std::int64_t(owned.size());
  MPI_Allreduce(MPI_IN_PLACE, &vertices, 1, MPI_INT64_T, MPI_SUM, comm.raw);
  if (vertices == 0)
    return count;
  // The same threshold, to the bit, on any partition of the same values.
  count.threshold = par::reproducible_sum(comm, owned) / double(vertices);

  // Above the mean: owned vertices and ghosts (the outer halo stays out of the graph).
  const std::size_t local_vertices = mesh.mesh().positions.size();
  std::vector<double> values(local_vertices, 0.0);
  std::copy(owned.begin(), owned.end(), values.begin());
  mesh.update_halo(values);
  std::vector<char> above(local_vertices, 0);
  std::vector<std::int64_t> ids(local_vertices);
  for (std::int32_t v = 0; v < std::int32_t(local_vertices); ++v) {
    above[v] = v < mesh.local_count() && values[v] > count.threshold;
    ids[v] = mesh.global_index(v);
  }
  const auto label = geom::label_regions_across_ranks(
      comm, mesh.topology().vertex_neighbors(), above, ids, mesh.owned_count(),
      [&](std::span<double> labels) { mesh.update_halo(labels); });

  std::int64_t local_counts[2] = {0, 0}, counts[2];
  for (std::int32_t v = 0; v < mesh.owned_count(); ++v)
    if (above[v]) {
      ++local_counts[1];
      local_counts[0] += label[v] == ids[v];
    }
  MPI_Allreduce(local_counts, counts, 2, MPI_INT64_T, MPI_SUM, comm.raw);
  count.regions = int(counts[0]);
  count.mean_vertices = count.regions ? double(counts[1]) / count.regions : 0.0;
  return count;
}

} // namespace texsim::pipelines::fem_rd
