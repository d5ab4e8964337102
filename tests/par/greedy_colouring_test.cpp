// par::greedy_colouring against the sequential greedy colouring on graphs split over 1, 2 and 3
// ranks: a ring, a random graph with many ties of the priority key, and a graph whose vertices
// are owned by one rank while the others own none.
#include "core/rng.hpp"
#include "par/greedy_colouring.hpp"

#include <gtest/gtest.h>
#include <mpi.h>

#include <algorithm>
#include <numeric>
#include <set>

namespace texsim::par {
namespace {

using Graph = std::vector<std::set<std::int64_t>>;

std::vector<std::int32_t> sequential_greedy(const Graph& graph,
                                            const std::function<std::uint64_t(std::int64_t)>& key) {
  std::vector<std::int64_t> visits(graph.size());
  std::iota(visits.begin(), visits.end(), 0);
  std::sort(visits.begin(), visits.end(), [&](std::int64_t a, std::int64_t b) {
    return std::pair(key(a), a) < std::pair(key(b), b);
  });
  std::vector<std::int32_t> classes(graph.size(), -1);
  for (const auto v : visits) {
    std::set<std::int32_t> taken;
    for (const auto u : graph[std::size_t(v)])
      taken.insert(classes[std::size_t(u)]);
    std::int32_t c = 0;
    while (taken.count(c))
      ++c;
    classes[std::size_t(v)] = c;
  }
  return classes;
}

/// Colours `graph` split into `rank_offsets` and returns every vertex's class on every rank.
std::vector<std::int32_t> distributed(const Comm& comm, const Graph& graph,
                                      const std::vector<std::int64_t>& rank_offsets,
                                      const std::function<std::uint64_t(std::int64_t)>& key,
                                      std::int32_t* classes) {
  OwnedAdjacency rows;
  for (auto v = rank_offsets[std::size_t(comm.rank)]; v < rank_offsets[std::size_t(comm.rank) + 1];
       ++v) {
    rows.neighbours.insert(rows.neighbours.end(), graph[std::size_t(v)].begin(),
                           graph[std::size_t(v)].end());
    rows.offsets.push_back(std::int64_t(rows.neighbours.size()));
  }
  const auto colouring = greedy_colouring(comm, rank_offsets, std::move(rows), key);
  *classes = colouring.classes;
  std::vector<int> counts, offsets;
  for (int r = 0; r < comm.size; ++r) {
    offsets.push_back(int(rank_offsets[std::size_t(r)]));
    counts.push_back(int(rank_offsets[std::size_t(r) + 1] - rank_offsets[std::size_t(r)]));
  }
  std::vector<std::int32_t> all(graph.size());
  MPI_Allgatherv(colouring.owned_class.data(), int(colouring.owned_class.size()), MPI_INT32_T,
                 all.data(), counts.data(), offsets.data(), MPI_INT32_T, comm.raw);
  return all;
}

std::vector<std::int64_t> even_runs(const Comm& comm, std::int64_t n) {
  std::vector<std::int64_t> offsets;
  for (int r = 0; r <= comm.size; ++r)
    offsets.push_back(n * r / comm.size);
  return offsets;
}

void expect_sequential(const Graph& graph, const std::vector<std::int64_t>& rank_offsets,
                       const std::function<std::uint64_t(std::int64_t)>& key) {
  const Comm comm = world();
  std::int32_t classes = 0;
  const auto got = distributed(comm, graph, rank_offsets, key, &classes);
  const auto expected = sequential_greedy(graph, key);
  EXPECT_EQ(got, expected);
  EXPECT_EQ(classes, *std::max_element(expected.begin(), expected.end()) + 1);
  for (std::size_t v = 0; v < graph.size(); ++v)
    for (const auto u : graph[v])
      EXPECT_NE(got[v], got[std::size_t(u)]) << v << " and " << u;
}

Graph random_graph(std::int64_t n, int edges_per_vertex, std::uint64_t seed) {
  const CounterRng rng(seed, 1);
  Graph graph(static_cast<std::size_t>(n));
  for (std::int64_t v = 0; v < n; ++v)
    for (int e = 0; e < edges_per_vertex; ++e) {
      // Mostly nearby ids (as a Morton order gives), sometimes anywhere.
      const double r = rng.uniform(std::uint64_t(v), std::uint32_t(e), 0);
      const std::int64_t u =
          r < 0.8 ? std::min(n - 1, v + 1 + std::int64_t(r * 20))
                  : std::int64_t(rng.uniform(std::uint64_t(v), std::uint32_t(e), 1) * double(n));
      if (u == v)
        continue;
      graph[std::size_t(v)].insert(u);
      graph[std::size_t(u)].insert(v);
    }
  return graph;
}

TEST(GreedyColouring, RingInIdOrder) {
  const std::int64_t n = 101; // odd: three classes
  Graph ring(static_cast<std::size_t>(n));
  for (std::int64_t v = 0; v < n; ++v) {
    ring[std::size_t(v)].insert((v + 1) % n);
    ring[std::size_t((v + 1) % n)].insert(v);
  }
  expect_sequential(ring, even_runs(world(), n), [](std::int64_t) { return 0; });
}

TEST(GreedyColouring, RandomGraphRandomAndTiedPriorities) {
  const Comm comm = world();
  const auto graph = random_graph(3000, 6, 7);
  const CounterRng rng(4, 2);
  expect_sequential(graph, even_runs(comm, 3000), [&](std::int64_t v) {
    const auto bits = rng.bits(std::uint64_t(v), 0, 0);
    return (std::uint64_t(bits[0]) << 32) | bits[1];
  });
  // Four key values only: most order comes from the ties' ids.
  expect_sequential(graph, even_runs(comm, 3000), [&](std::int64_t v) {
    return std::uint64_t(rng.bits(std::uint64_t(v), 1, 0)[0] % 4);
  });
  // Priorities against the ids: every chain runs backwards through the ranks.
  expect_sequential(graph, even_runs(comm, 3000),
                    [](std::int64_t v) { return std::uint64_t(3000 - v); });
}

TEST(GreedyColouring, RanksWithoutVertices) {
  const Comm comm = world();
  const auto graph = random_graph(500, 4, 9);
  std::vector<std::int64_t> offsets(std::size_t(comm.size) + 1, 500);
  offsets[0] = 0; // rank 0 owns everything
  expect_sequential(graph, offsets, [](std::int64_t v) { return std::uint64_t(v * 7919 % 500); });
}

TEST(GreedyColouring, AsymmetricGraphIsRefusedOnEveryRank) {
  const Comm comm = world();
  // Vertex 0 (rank 0) lists vertex n-1 (the last rank) but not the other way round, and vertex
  // n-1 comes first: vertex 0 waits for a class nobody sends.
  const std::int64_t n = 10;
  const auto offsets = even_runs(comm, n);
  OwnedAdjacency rows;
  for (auto v = offsets[std::size_t(comm.rank)]; v < offsets[std::size_t(comm.rank) + 1]; ++v) {
    if (v == 0)
      rows.neighbours.push_back(n - 1);
    rows.offsets.push_back(std::int64_t(rows.neighbours.size()));
  }
  EXPECT_THROW(greedy_colouring(comm, offsets, std::move(rows),
                                [&](std::int64_t v) { return std::uint64_t(n - v); }),
               std::exception);
}

} // namespace
} // namespace texsim::par
