#include "pipelines/fem_rd/pattern_regions.hpp"

#include "geom/graph_regions.hpp"

#include <algorithm>
#include <numeric>
#include <vector>

namespace texsim::pipelines::fem_rd {

RegionCount count_regions_above_mean(const geom::MeshTopology& topology,
                                     std::span<const double> values) {
  RegionCount count;
  if (values.empty())
    return count;
  count.threshold = std::accumulate(values.begin(), values.end(), 0.0) / double(values.size());
  std::vector<char> above(values.size());
  for (std::size_t v = 0; v < values.size(); ++v)
    above[v] = values[v] > count.threshold;
  const auto labels = geom::label_regions(topology.vertex_neighbors(), above);
  count.regions = 1 + *std::max_element(labels.begin(), labels.end());
  const auto vertices_above = std::count(above.begin(), above.end(), 1);
  count.mean_vertices = count.regions ? double(vertices_above) / count.regions : 0.0;
  return count;
}

} // namespace texsim::pipelines::fem_rd
