#pragma once
/// Wei-Levoy visit the vertices of a level in random order (Section 3.2). texsim visits them in
/// colour classes of the conflict graph (u and v conflict when one's stencil reads the other),
/// coloured greedily in the order of Philox priorities keyed by (seed, level, pass, id): no member
/// of a class reads another, so a class is synthesised concurrently by every rank and thread with
/// the result of one sequential random order, and the classes and their order depend on neither
/// the rank count nor the thread count.
#include "par/comm.hpp"
#include "pipelines/surface_synthesis/level_stencils.hpp"

#include <cstdint>
#include <span>
#include <vector>

namespace texsim::pipelines::surface_synthesis {

struct SynthesisOrder {
  std::int32_t classes = 0;
  /// Class of each owned vertex (local index from LevelStencils::first).
  std::vector<std::int32_t> owned_class;
  /// Owned vertices (local indices) of each class, increasing.
  std::vector<std::vector<std::int64_t>> owned_members;
};

/// The priority key of vertex `id` in the greedy colouring of (level, pass): smaller first, equal
/// keys by smaller id.
std::uint64_t synthesis_priority(std::uint64_t seed, int level, Pass pass, std::int64_t id);

/// The classes of one pass over the level split into `rank_offsets` (the stencils are this rank's
/// run): pass 1 reads only the coarser level, so nothing conflicts and it is one class; pass 2
/// colours the conflicts of the current-part stencils with par::greedy_colouring, each rank
/// holding the conflicts of its own vertices only. Collective.
SynthesisOrder synthesis_order(const par::Comm& comm, const LevelStencils& stencils,
                               std::span<const std::int64_t> rank_offsets, std::uint64_t seed,
                               int level, Pass pass);

} // namespace texsim::pipelines::surface_synthesis
