// Scotch's partition of a graph must be a pure function of the graph and the part count: the same
// on every rank and on every call (PT-Scotch was not), balanced, and far better than a random cut.
// The graph is a 3D lattice, where the ideal cut is known.
#include "par/graph_partition.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <vector>

namespace texsim::par {
namespace {

struct Graph {
  std::vector<std::int64_t> offsets{0};
  std::vector<std::int32_t> neighbors;
};

/// The n x n x n lattice with 6-neighbour edges.
Graph lattice(int n) {
  Graph graph;
  const auto id = [n](int x, int y, int z) { return std::int32_t(x + n * (y + n * z)); };
  for (int z = 0; z < n; ++z)
    for (int y = 0; y < n; ++y)
      for (int x = 0; x < n; ++x) {
        for (const auto& [dx, dy, dz] :
             {std::array{-1, 0, 0}, std::array{1, 0, 0}, std::array{0, -1, 0}, std::array{0, 1, 0},
              std::array{0, 0, -1}, std::array{0, 0, 1}}) {
          const int a = x + dx, b = y + dy, c = z + dz;
          if (a >= 0 && a < n && b >= 0 && b < n && c >= 0 && c < n)
            graph.neighbors.push_back(id(a, b, c));
        }
        graph.offsets.push_back(std::int64_t(graph.neighbors.size()));
      }
  return graph;
}

std::int64_t edge_cut(const Graph& graph, const std::vector<int>& part) {
  std::int64_t cut = 0;
  for (std::size_t v = 0; v + 1 < graph.offsets.size(); ++v)
    for (auto e = graph.offsets[v]; e < graph.offsets[v + 1]; ++e)
      cut += part[v] != part[std::size_t(graph.neighbors[std::size_t(e)])];
  return cut / 2;
}

TEST(ScotchGraphPartition, SameOnEveryRankAndEveryCall) {
  const Comm comm = world();
  const Graph graph = lattice(24);
  for (const int parts : {2, 3, 7}) {
    const auto first = scotch_graph_partition(comm, graph.offsets, graph.neighbors, parts);
    const auto second = scotch_graph_partition(comm, graph.offsets, graph.neighbors, parts);
    EXPECT_EQ(first, second) << parts << " parts";
    // Rank 0's answer reaches everyone: compare with a broadcast copy.
    auto root_copy = first;
    MPI_Bcast(root_copy.data(), int(root_copy.size()), MPI_INT, 0, comm.raw);
    EXPECT_EQ(root_copy, first);
  }
}

TEST(ScotchGraphPartition, BalancedWithANearOptimalCut) {
  const int n = 24;
  const Graph graph = lattice(n);
  const auto part = scotch_graph_partition(world(), graph.offsets, graph.neighbors, 2);
  const auto ones = std::count(part.begin(), part.end(), 1);
  const double half = n * n * n / 2.0;
  EXPECT_LE(std::abs(double(ones) - half), 0.011 * half);
  // Bisecting the cube by a plane cuts n^2 edges; a random split cuts about half of 3n^2(n-1).
  EXPECT_LE(edge_cut(graph, part), 1.3 * n * n);
}

TEST(ScotchGraphPartition, OnePartIsEverything) {
  const Graph graph = lattice(4);
  const auto part = scotch_graph_partition(world(), graph.offsets, graph.neighbors, 1);
  EXPECT_EQ(part, std::vector<int>(64, 0));
}

} // namespace
} // namespace texsim::par
