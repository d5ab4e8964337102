#include "pipelines/fem_rd/pattern_regions.hpp"

#include <numeric>
#include <vector>

namespace texsim::pipelines::fem_rd {

RegionCount count_regions_above_mean(const geom::MeshTopology& topology,
                                     std::span<const double> values) {
  RegionCount count;
  if (values.empty())
    return count;
  count.threshold = std::accumulate(values.begin(), values.end(), 0.0) / double(values.size());
  const auto& neighbors = topology.vertex_neighbors();
  std::vector<char> seen(values.size(), 0);
  std::vector<std::int32_t> stack;
  std::int64_t above = 0;
  for (std::int32_t start = 0; start < std::int32_t(values.size()); ++start) {
    if (seen[start] || values[start] <= count.threshold)
      continue;
    ++count.regions;
    seen[start] = 1;
    stack.push_back(start);
    while (!stack.empty()) {
      const std::int32_t v = stack.back();
      stack.pop_back();
      ++above;
      for (const std::int32_t w : neighbors.row(v))
        if (!seen[w] && values[w] > count.threshold) {
          seen[w] = 1;
          stack.push_back(w);
        }
    }
  }
  count.mean_vertices = count.regions ? double(above) / count.regions : 0.0;
  return count;
}

} // namespace texsim::pipelines::fem_rd
