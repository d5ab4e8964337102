#pragma once
/// Greedy colouring of a graph whose vertices are split over the ranks in runs of ids
/// (par/id_runs.hpp): in a total priority order, each vertex takes the smallest class that none of
/// its earlier neighbours took, the colouring the sequential greedy algorithm gives when it visits
/// the vertices in that order. It is computed by Jones and Plassmann's rounds: a vertex is coloured
/// as soon as all its earlier neighbours are; in each round a rank colours every owned vertex that
/// becomes ready, then sends the new classes to the ranks whose vertices wait on them. So the
/// classes are the same for any rank count, and a rank holds only its rows and their neighbours'
/// classes.
#include "par/comm.hpp"

#include <cstdint>
#include <functional>
#include <span>
#include <vector>

namespace texsim::par {

/// A rank's rows of the graph: the neighbours (global ids) of each owned vertex, in CSR form.
struct OwnedAdjacency {
  std::vector<std::int64_t> offsets{0}; ///< owned + 1 entries
  std::vector<std::int64_t> neighbours; ///< no repeats and no self within a row
};

struct GreedyColouring {
  std::vector<std::int32_t> owned_class; ///< class of each owned vertex, from 0
  std::int32_t classes = 0;              ///< over all ranks
};

/// Colours the graph whose rows `adjacency` holds for this rank's run of `rank_offsets` (taken by
/// value: its ids become local slots in place, so the caller should move it in). The graph
/// must be symmetric across ranks (v in u's row exactly when u is in v's). `priority(id)` is the
/// order's key of any vertex id, the same on every rank: smaller keys come first, equal keys by
/// smaller id. Throws an internal error if no vertex can be coloured (an asymmetric graph) rather
/// than hanging. Collective.
GreedyColouring greedy_colouring(const Comm& comm, std::span<const std::int64_t> rank_offsets,
                                 OwnedAdjacency adjacency,
                                 const std::function<std::uint64_t(std::int64_t)>& priority);

} // namespace texsim::par
