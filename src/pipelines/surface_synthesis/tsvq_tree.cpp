#include "pipelines/surface_synthesis/tsvq_tree.hpp"

#include "core/error.hpp"

#include <algorithm>
#include <numeric>

namespace texsim::pipelines::surface_synthesis {
namespace {

/// Squared distance between a float row and a double vector, as exact_distance2.
double distance_to(const float* row, const double* point, int dimension) {
  return exact_distance2(row, 1, point, dimension);
}

} // namespace

TsvqSearch::TsvqSearch(NeighbourhoodTable table, std::int64_t leaf_size, int iterations)
    : NeighbourhoodSearch(std::move(table)) {
  TEXSIM_VERIFY(leaf_size >= 1 && iterations >= 1, "TSVQ: leaf size "
                                                       << leaf_size << " and iterations "
                                                       << iterations << " must be >= 1");
  order_.resize(static_cast<std::size_t>(rows()));
  std::iota(order_.begin(), order_.end(), std::int64_t{0});
  add_node(0, rows());
  const int d = dimension();
  const float* values = this->table().values.data();
  // The root's centroid: the mean of all rows (the children's come from their split).
  for (std::int64_t r = 0; r < rows(); ++r)
    for (int c = 0; c < d; ++c)
      centroids_[static_cast<std::size_t>(c)] += values[r * d + c];
  for (int c = 0; c < d; ++c)
    centroids_[static_cast<std::size_t>(c)] /= static_cast<double>(rows());
  // Depth first, an explicit stack: an unbalanced tree may be deep.
  std::vector<std::int32_t> pending{0};
  while (!pending.empty()) {
    const std::int32_t node = pending.back();
    pending.pop_back();
    split(node, leaf_size, iterations);
    if (nodes_[node].left >= 0) {
      pending.push_back(nodes_[node].right);
      pending.push_back(nodes_[node].left);
    }
  }
}

std::int32_t TsvqSearch::add_node(std::int64_t first, std::int64_t count) {
  nodes_.push_back({-1, -1, first, count});
  centroids_.resize(nodes_.size() * static_cast<std::size_t>(dimension()), 0.0);
  return static_cast<std::int32_t>(nodes_.size() - 1);
}

void TsvqSearch::split(std::int32_t node, std::int64_t leaf_size, int iterations) {
  const Node span = nodes_[node];
  if (span.count <= leaf_size)
    return;
  const int d = dimension();
  const auto dims = static_cast<std::size_t>(d);
  const float* values = table().values.data();
  const std::int64_t* rows = order_.data() + span.first;
  const auto row = [&](std::int64_t i) { return values + rows[i] * d; };

  // Seeds: the farthest row from the first one, then the farthest from that (ties: lower row).
  const auto farthest_from = [&](std::int64_t from, double& distance) {
    std::vector<double> point(row(from), row(from) + d);
    std::int64_t best = from;
    distance = 0.0;
    for (std::int64_t i = 0; i < span.count; ++i) {
      const double di = distance_to(row(i), point.data(), d);
      if (di > distance) {
        distance = di;
        best = i;
      }
    }
    return best;
  };
  double spread = 0.0;
  const std::int64_t a = farthest_from(0, spread);
  const std::int64_t b = farthest_from(a, spread);
  if (spread == 0.0) // all rows equal: no split exists
    return;

  std::vector<double> centres[2] = {std::vector<double>(row(a), row(a) + d),
                                    std::vector<double>(row(b), row(b) + d)};
  std::vector<char> side(static_cast<std::size_t>(span.count), 0);
  std::vector<char> next(side.size());
  for (int round = 0; round < iterations; ++round) {
    std::int64_t right = 0;
    for (std::int64_t i = 0; i < span.count; ++i) {
      next[i] = distance_to(row(i), centres[1].data(), d) <
                distance_to(row(i), centres[0].data(), d); // ties to the left
      right += next[i];
    }
    if ((round > 0 && next == side) || right == 0 || right == span.count)
      break;
    side.swap(next);
    for (auto& centre : centres)
      std::fill(centre.begin(), centre.end(), 0.0);
    std::int64_t counts[2] = {0, 0};
    for (std::int64_t i = 0; i < span.count; ++i) {
      auto& centre = centres[static_cast<int>(side[i])];
      ++counts[static_cast<int>(side[i])];
      for (int c = 0; c < d; ++c)
        centre[static_cast<std::size_t>(c)] += row(i)[c];
    }
    for (int s = 0; s < 2; ++s)
      for (double& value : centres[s])
        value /= static_cast<double>(counts[s]);
  }

  const auto left_count =
      static_cast<std::int64_t>(std::count(side.begin(), side.end(), static_cast<char>(0)));
  if (left_count == 0 || left_count == span.count) // cannot happen with distinct seeds; stay a leaf
    return;
  // Left rows first, each side ascending.
  std::vector<std::int64_t> grouped;
  grouped.reserve(side.size());
  for (int s = 0; s < 2; ++s)
    for (std::int64_t i = 0; i < span.count; ++i)
      if (side[i] == s)
        grouped.push_back(rows[i]);
  std::copy(grouped.begin(), grouped.end(), order_.begin() + span.first);
  const std::int32_t left = add_node(span.first, left_count);
  const std::int32_t right = add_node(span.first + left_count, span.count - left_count);
  std::copy(centres[0].begin(), centres[0].end(), centroids_.begin() + left * dims);
  std::copy(centres[1].begin(), centres[1].end(), centroids_.begin() + right * dims);
  nodes_[node].left = left;
  nodes_[node].right = right;
}

double TsvqSearch::distance_to_centroid(std::int32_t node, std::span<const double> query) const {
  // The same sum as exact_distance2, with the centroid's doubles in place of a row's floats.
  const double* centroid = centroids_.data() + static_cast<std::size_t>(node) * dimension();
  double sum = 0.0;
  for (int c = 0; c < dimension(); ++c) {
    const double diff = centroid[c] - query[c];
    sum += diff * diff;
  }
  return sum;
}

std::int32_t TsvqSearch::leaf_of(std::span<const double> query) const {
  check_query(query);
  std::int32_t node = 0;
  while (nodes_[node].left >= 0) {
    const Node& n = nodes_[node];
    node = distance_to_centroid(n.right, query) < distance_to_centroid(n.left, query) ? n.right
                                                                                      : n.left;
  }
  return node;
}

std::int64_t TsvqSearch::nearest(std::span<const double> query) const {
  const Node& leaf = nodes_[leaf_of(query)];
  return nearest_among(std::span(order_).subspan(static_cast<std::size_t>(leaf.first),
                                                 static_cast<std::size_t>(leaf.count)),
                       query);
}

int TsvqSearch::depth() const {
  std::vector<int> level(nodes_.size(), 0);
  int deepest = 0;
  for (std::size_t n = 0; n < nodes_.size(); ++n) // children come after their parent
    if (nodes_[n].left >= 0) {
      level[nodes_[n].left] = level[nodes_[n].right] = level[n] + 1;
      deepest = std::max(deepest, level[n] + 1);
    }
  return deepest;
}

std::size_t TsvqSearch::memory_bytes() const {
  return table().values.capacity() * sizeof(float) + nodes_.capacity() * sizeof(Node) +
         centroids_.capacity() * sizeof(double) + order_.capacity() * sizeof(std::int64_t);
}

} // namespace texsim::pipelines::surface_synthesis
