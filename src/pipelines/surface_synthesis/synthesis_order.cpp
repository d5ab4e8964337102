#include "pipelines/surface_synthesis/synthesis_order.hpp"

#include "core/rng.hpp"
#include "geom/mesh_topology.hpp"

#include <mpi.h>

#include <algorithm>
#include <numeric>

namespace texsim::pipelines::surface_synthesis {
namespace {

constexpr std::uint32_t kOrderStream = 0x5301;

/// All ranks' (reader, read) pairs, both directions, as a CSR graph over the level's vertices.
geom::CsrAdjacency conflict_graph(const par::Comm& comm, const LevelStencils& stencils,
                                  std::int64_t vertices) {
  std::vector<std::int64_t> pairs;
  std::vector<std::int64_t> read;
  for (std::int64_t local = 0; local < stencils.owned; ++local) {
    const std::int64_t u = stencils.first + local;
    read.clear();
    for (const auto& sample : stencils.current_of(local))
      if (sample.covered())
        for (int k = 0; k < 3; ++k)
          if (sample.weights[std::size_t(k)] != 0.0 && sample.vertices[std::size_t(k)] != u)
            read.push_back(sample.vertices[std::size_t(k)]);
    std::sort(read.begin(), read.end());
    read.erase(std::unique(read.begin(), read.end()), read.end());
    for (const std::int64_t v : read)
      pairs.insert(pairs.end(), {u, v});
  }
  int local_count = int(pairs.size());
  std::vector<int> counts(std::size_t(comm.size)), offsets(std::size_t(comm.size));
  MPI_Allgather(&local_count, 1, MPI_INT, counts.data(), 1, MPI_INT, comm.raw);
  std::exclusive_scan(counts.begin(), counts.end(), offsets.begin(), 0);
  std::vector<std::int64_t> all(std::size_t(offsets.back() + counts.back()));
  MPI_Allgatherv(pairs.data(), local_count, MPI_INT64_T, all.data(), counts.data(), offsets.data(),
                 MPI_INT64_T, comm.raw);

  geom::CsrAdjacency graph;
  graph.offsets.assign(std::size_t(vertices) + 1, 0);
  for (std::size_t k = 0; k < all.size(); k += 2) {
    ++graph.offsets[std::size_t(all[k]) + 1];
    ++graph.offsets[std::size_t(all[k + 1]) + 1];
  }
  std::partial_sum(graph.offsets.begin(), graph.offsets.end(), graph.offsets.begin());
  graph.indices.resize(std::size_t(graph.offsets.back()));
  auto fill = graph.offsets;
  for (std::size_t k = 0; k < all.size(); k += 2) {
    graph.indices[std::size_t(fill[std::size_t(all[k])]++)] = std::int32_t(all[k + 1]);
    graph.indices[std::size_t(fill[std::size_t(all[k + 1])]++)] = std::int32_t(all[k]);
  }
  return graph;
}

} // namespace

SynthesisOrder synthesis_order(const par::Comm& comm, const LevelStencils& stencils,
                               std::int64_t vertices, std::uint64_t seed, int level, Pass pass) {
  SynthesisOrder order;
  order.class_of.assign(std::size_t(vertices), 0);
  if (pass == Pass::extrapolate) {
    order.classes = 1;
  } else {
    const auto graph = conflict_graph(comm, stencils, vertices);
    // Priority order: a random permutation keyed by (seed, level, pass), ties by id.
    const CounterRng rng(seed, kOrderStream);
    std::vector<std::pair<std::uint64_t, std::int64_t>> ranked(static_cast<std::size_t>(vertices));
    for (std::int64_t v = 0; v < vertices; ++v) {
      const auto bits = rng.bits(std::uint64_t(v), std::uint32_t(level), std::uint32_t(pass));
      ranked[std::size_t(v)] = {(std::uint64_t(bits[0]) << 32) | bits[1], v};
    }
    std::sort(ranked.begin(), ranked.end());
    std::fill(order.class_of.begin(), order.class_of.end(), -1);
    std::vector<std::int32_t> used_by(64, -1); // used_by[c] == v: colour c taken near v
    for (const auto& [key, v] : ranked) {
      for (const std::int32_t u : graph.row(std::int32_t(v))) {
        const std::int32_t c = order.class_of[std::size_t(u)];
        if (c < 0)
          continue;
        if (std::size_t(c) >= used_by.size())
          used_by.resize(std::size_t(c) + 1, -1);
        used_by[std::size_t(c)] = std::int32_t(v);
      }
      std::int32_t colour = 0;
      while (std::size_t(colour) < used_by.size() && used_by[std::size_t(colour)] == v)
        ++colour;
      order.class_of[std::size_t(v)] = colour;
      order.classes = std::max(order.classes, colour + 1);
    }
  }
  order.owned_members.resize(std::size_t(order.classes));
  for (std::int64_t local = 0; local < stencils.owned; ++local)
    order.owned_members[std::size_t(order.class_of[std::size_t(stencils.first + local)])].push_back(
        local);
  return order;
}

} // namespace texsim::pipelines::surface_synthesis
