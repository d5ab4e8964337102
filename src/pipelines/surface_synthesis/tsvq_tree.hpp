#pragma once
/// Tree-structured vector quantisation (Wei-Levoy 2000, section 4.1), the approximate search: a
/// binary tree built by recursive 2-means over the neighbourhood vectors; a query descends to the
/// nearer child centroid at each node and is matched exactly against the rows of the leaf it
/// reaches.
///
/// Deterministic build: a node's rows are split by Lloyd iterations started from two rows far
/// apart (a = the row farthest from the node's first row, b = the row farthest from a; ties to the
/// lower row), each row going to the nearer centroid (ties to the left), centroids = means summed
/// in row order, until the assignment stops changing or after `iterations` rounds. A node becomes
/// a leaf when it holds at most `leaf_size` rows or all its rows are equal (then no split exists);
/// a round that would empty a side is not taken. Queries descend to the left child on a tie.
///
/// Testing against the exact search: with leaf_size >= rows the root is the only leaf and TSVQ
/// returns exactly what the exhaustive search returns.
#include "pipelines/surface_synthesis/neighbourhood_search.hpp"

#include <vector>

namespace texsim::pipelines::surface_synthesis {

class TsvqSearch final : public NeighbourhoodSearch {
public:
  /// A node of the tree: children (-1 in a leaf) and its rows, ascending, as
  /// rows_in_order()[first, first + count).
  struct Node {
    std::int32_t left = -1;
    std::int32_t right = -1;
    std::int64_t first = 0;
    std::int64_t count = 0;
  };

  /// Builds the tree (leaf_size >= 1, iterations >= 1).
  TsvqSearch(NeighbourhoodTable table, std::int64_t leaf_size, int iterations);

  std::int64_t nearest(std::span<const double> query) const override;
  std::size_t memory_bytes() const override;

  /// Nodes, the root first.
  const std::vector<Node>& nodes() const { return nodes_; }
  /// Node centroids (nodes().size() x dimension, node-major): the mean of each node's rows.
  const std::vector<double>& centroids() const { return centroids_; }
  /// The rows grouped by node: every node's rows are a contiguous ascending run.
  const std::vector<std::int64_t>& rows_in_order() const { return order_; }
  /// The leaf a query descends to.
  std::int32_t leaf_of(std::span<const double> query) const;
  /// Longest root-to-leaf path (edges).
  int depth() const;

private:
  void split(std::int32_t node, std::int64_t leaf_size, int iterations);
  std::int32_t add_node(std::int64_t first, std::int64_t count);
  double distance_to_centroid(std::int32_t node, std::span<const double> query) const;

  std::vector<Node> nodes_;
  std::vector<double> centroids_;
  std::vector<std::int64_t> order_;
};

} // namespace texsim::pipelines::surface_synthesis
