#pragma once
/// Exact totals per label of quantities spread over ranks (a pattern's regions: each region's area,
/// moments and border, from the cells each rank owns), the same bits for any split over ranks and
/// any order of the items: every quantity is sliced on fixed grids (par::SliceGrids), each rank
/// adds its items' slices per label, and rank 0 adds the ranks' partial sums label by label,
/// exactly. O(labels) data moves, not O(items).
#include "par/comm.hpp"

#include <cstdint>
#include <span>
#include <vector>

namespace texsim::par {

struct LabelledTotal {
  std::int64_t label = 0;
  std::int64_t count = 0;   ///< items with this label, over all ranks
  std::vector<double> sums; ///< `width` totals
};

/// Item i of this rank has label `labels[i]` (below 2^53; negative: left out) and the quantities
/// `quantities[width * i ... width * i + width - 1]` (finite). Rank 0 gets every label's total in
/// increasing label order; the other ranks get nothing. Collective.
std::vector<LabelledTotal> labelled_sums_on_root(const Comm& comm,
                                                 std::span<const std::int64_t> labels,
                                                 std::span<const double> quantities,
                                                 std::size_t width);

} // namespace texsim::par
