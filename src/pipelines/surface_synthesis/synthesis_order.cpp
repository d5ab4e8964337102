#include "pipelines/surface_synthesis/synthesis_order.hpp"

#include "core/rng.hpp"
#include "par/greedy_colouring.hpp"
#include "par/id_runs.hpp"
#include "par/record_exchange.hpp"

#include <algorithm>
#include <numeric>

namespace texsim::pipelines::surface_synthesis {
namespace {

constexpr std::uint32_t kOrderStream = 0x5301;

/// A read of `vertex` by `reader`, sent to the owner of `vertex` (level ids fit 32 bits).
struct Read {
  std::int32_t vertex;
  std::int32_t reader;
};

/// The conflict rows of this rank's vertices: the vertices each one's current-part stencil reads
/// (nonzero weight, not itself) and the vertices whose stencils read it (reads of a vertex owned
/// elsewhere go to its owner). Both lists are built by counting, as CSR, then merged per row.
par::OwnedAdjacency conflict_rows(const par::Comm& comm, const LevelStencils& stencils,
                                  std::span<const std::int64_t> rank_offsets) {
  const std::int64_t first = stencils.first;
  const std::int64_t owned = stencils.owned;
  const auto is_owned = [&](std::int64_t v) { return v >= first && v < first + owned; };
  std::vector<std::int64_t> read_offsets{0};
  std::vector<std::int32_t> reads; // per owned vertex, increasing
  std::vector<std::vector<Read>> outgoing(std::size_t(comm.size));
  for (std::int64_t local = 0; local < owned; ++local) {
    const auto u = std::int32_t(first + local);
    const auto row_begin = reads.size();
    for (const auto& sample : stencils.current_of(local))
      if (sample.covered())
        for (int k = 0; k < 3; ++k)
          if (sample.weights[std::size_t(k)] != 0.0f && sample.vertices[std::size_t(k)] != u)
            reads.push_back(sample.vertices[std::size_t(k)]);
    const auto row = reads.begin() + std::ptrdiff_t(row_begin);
    std::sort(row, reads.end());
    reads.erase(std::unique(row, reads.end()), reads.end());
    read_offsets.push_back(std::int64_t(reads.size()));
    for (auto v = row; v != reads.end(); ++v)
      if (!is_owned(*v))
        outgoing[std::size_t(par::owner_of(rank_offsets, *v))].push_back({*v, u});
  }
  const auto received = par::exchange_records(comm, outgoing);
  outgoing = {};

  // Who reads each owned vertex: this rank's reads of its own vertices and the received ones.
  std::vector<std::int64_t> reader_offsets(std::size_t(owned) + 1, 0);
  for (const std::int32_t v : reads)
    if (is_owned(v))
      ++reader_offsets[std::size_t(v - first) + 1];
  for (const auto& read : received)
    ++reader_offsets[std::size_t(read.vertex - first) + 1];
  std::partial_sum(reader_offsets.begin(), reader_offsets.end(), reader_offsets.begin());
  std::vector<std::int32_t> readers(std::size_t(reader_offsets.back()));
  {
    auto fill = reader_offsets;
    for (std::int64_t local = 0; local < owned; ++local)
      for (auto k = read_offsets[std::size_t(local)]; k < read_offsets[std::size_t(local) + 1]; ++k)
        if (const std::int32_t v = reads[std::size_t(k)]; is_owned(v))
          readers[std::size_t(fill[std::size_t(v - first)]++)] = std::int32_t(first + local);
    for (const auto& read : received)
      readers[std::size_t(fill[std::size_t(read.vertex - first)]++)] = read.reader;
  }

  // Each row is the union of the two increasing lists (u reading v and v reading u: one entry).
  const auto read_row = [&](std::int64_t local) {
    return std::span(reads).subspan(
        std::size_t(read_offsets[std::size_t(local)]),
        std::size_t(read_offsets[std::size_t(local) + 1] - read_offsets[std::size_t(local)]));
  };
  const auto reader_row = [&](std::int64_t local) {
    return std::span(readers).subspan(
        std::size_t(reader_offsets[std::size_t(local)]),
        std::size_t(reader_offsets[std::size_t(local) + 1] - reader_offsets[std::size_t(local)]));
  };
  par::OwnedAdjacency rows;
  rows.offsets.assign(std::size_t(owned) + 1, 0);
  for (std::int64_t local = 0; local < owned; ++local) {
    const auto by = reader_row(local);
    std::sort(by.begin(), by.end());
    const auto of = read_row(local);
    std::size_t shared = 0;
    for (std::size_t i = 0, j = 0; i < of.size() && j < by.size();)
      if (of[i] < by[j])
        ++i;
      else if (by[j] < of[i])
        ++j;
      else
        ++shared, ++i, ++j;
    rows.offsets[std::size_t(local) + 1] =
        rows.offsets[std::size_t(local)] + std::int64_t(of.size() + by.size() - shared);
  }
  rows.neighbours.resize(std::size_t(rows.offsets.back()));
  for (std::int64_t local = 0; local < owned; ++local) {
    const auto of = read_row(local);
    const auto by = reader_row(local);
    std::set_union(of.begin(), of.end(), by.begin(), by.end(),
                   rows.neighbours.begin() + rows.offsets[std::size_t(local)]);
  }
  return rows;
}

} // namespace

std::uint64_t synthesis_priority(std::uint64_t seed, int level, Pass pass, std::int64_t id) {
  const auto bits = CounterRng(seed, kOrderStream)
                        .bits(std::uint64_t(id), std::uint32_t(level), std::uint32_t(pass));
  return (std::uint64_t(bits[0]) << 32) | bits[1];
}

SynthesisOrder synthesis_order(const par::Comm& comm, const LevelStencils& stencils,
                               std::span<const std::int64_t> rank_offsets, std::uint64_t seed,
                               int level, Pass pass) {
  SynthesisOrder order;
  if (pass == Pass::extrapolate) {
    order.classes = 1;
    order.owned_class.assign(std::size_t(stencils.owned), 0);
  } else {
    auto colouring = par::greedy_colouring(
        comm, rank_offsets, conflict_rows(comm, stencils, rank_offsets),
        [&](std::int64_t id) { return synthesis_priority(seed, level, pass, id); });
    order.classes = colouring.classes;
    order.owned_class = std::move(colouring.owned_class);
  }
  order.owned_members.resize(std::size_t(order.classes));
  for (std::int64_t local = 0; local < stencils.owned; ++local)
    order.owned_members[std::size_t(order.owned_class[std::size_t(local)])].push_back(local);
  return order;
}

} // namespace texsim::pipelines::surface_synthesis
