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
#include <vector>

namespace texsim::pipelines::surface_synthesis {

struct SynthesisOrder {
  /// Class of every vertex of the level (all ranks hold all).
  std::vector<std::int32_t> class_of;
  std::int32_t classes = 0;
  /// Owned vertices (local indices from LevelStencils::first) of each class, increasing.
  std::vector<std::vector<std::int64_t>> owned_members;
};

/// The classes of one pass: pass 1 reads only the coarser level, so nothing conflicts and it is
/// one class; pass 2 colours the conflicts of the current-part stencils. Collective (the conflict
/// pairs are all-gathered: geometry is replicated for now).
SynthesisOrder synthesis_order(const par::Comm& comm, const LevelStencils& stencils,
                               std::int64_t vertices, std::uint64_t seed, int level, Pass pass);

} // namespace texsim::pipelines::surface_synthesis
