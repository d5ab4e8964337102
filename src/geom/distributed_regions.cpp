#include "geom/distributed_regions.hpp"

#include "core/error.hpp"
#include "geom/graph_regions.hpp"

#include <mpi.h>

#include <algorithm>
#include <limits>

namespace texsim::geom {

std::vector<std::int64_t>
label_regions_across_ranks(const par::Comm& comm, const CsrAdjacency& local_neighbors,
                           std::span<const char> marked, std::span<const std::int64_t> global_ids,
                           std::int32_t owned_count, const GhostUpdate& update_ghosts) {
  const std::size_t nodes = marked.size();
  TEXSIM_VERIFY(local_neighbors.rows() == std::int32_t(nodes) && global_ids.size() == nodes &&
                    owned_count <= std::int32_t(nodes),
                "regions across ranks: " << local_neighbors.rows() << " adjacency rows, "
                                         << global_ids.size() << " ids and " << nodes
                                         << " marks for " << owned_count << " owned nodes");
  const auto components = label_regions(local_neighbors, marked);
  const std::int32_t component_count =
      nodes ? 1 + std::max(-1, *std::max_element(components.begin(), components.end())) : 0;

  // Each local component takes the smallest label any of its nodes carries; the ghosts then take
  // their owners' labels. Labels only fall, so this ends. (Labels travel as doubles: ids below
  // 2^53 are exact.)
  constexpr double kNone = std::numeric_limits<double>::infinity();
  std::vector<double> label(nodes, kNone);
  for (std::size_t v = 0; v < nodes; ++v)
    if (marked[v])
      label[v] = double(global_ids[v]);
  for (int changed = 1; changed;) {
    std::vector<double> smallest(std::size_t(component_count), kNone);
    for (std::size_t v = 0; v < nodes; ++v)
      if (components[v] >= 0)
        smallest[components[v]] = std::min(smallest[components[v]], label[v]);
    int mine = 0;
    for (std::size_t v = 0; v < nodes; ++v)
      if (components[v] >= 0 && smallest[components[v]] < label[v]) {
        mine |= std::int32_t(v) < owned_count;
        label[v] = smallest[components[v]];
      }
    update_ghosts(label);
    MPI_Allreduce(&mine, &changed, 1, MPI_INT, MPI_LOR, comm.raw);
  }
  std::vector<std::int64_t> regions(nodes, -1);
  for (std::size_t v = 0; v < nodes; ++v)
    if (marked[v])
      regions[v] = std::int64_t(label[v]);
  return regions;
}

} // namespace texsim::geom
