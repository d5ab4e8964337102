#include "geom/graph_regions.hpp"

namespace texsim::geom {

std::vector<std::int32_t> label_regions(const CsrAdjacency& neighbors,
                                        std::span<const char> marked) {
  std::vector<std::int32_t> label(marked.size(), -1);
  std::vector<std::int32_t> stack;
  std::int32_t regions = 0;
  for (std::int32_t start = 0; start < std::int32_t(marked.size()); ++start) {
    if (!marked[start] || label[start] >= 0)
      continue;
    label[start] = regions;
    stack.push_back(start);
    while (!stack.empty()) {
      const std::int32_t v = stack.back();
      stack.pop_back();
      for (const std::int32_t w : neighbors.row(v))
        if (marked[w] && label[w] < 0) {
          label[w] = regions;
          stack.push_back(w);
        }
    }
    ++regions;
  }
  return label;
}

} // namespace texsim::geom
