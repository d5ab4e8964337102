#pragma once
/// Ids split over the ranks in runs: rank r owns [rank_offsets[r], rank_offsets[r + 1]), the table
/// holding comm.size + 1 non-decreasing entries from 0 to the total.
#include <algorithm>
#include <cstdint>
#include <span>

namespace texsim::par {

/// The first id of rank `rank`'s run when `count` ids are split into `ranks` even runs:
/// [count r / p, count (r + 1) / p).
inline std::int64_t even_run_begin(std::int64_t count, int rank, int ranks) {
  return count * rank / ranks;
}

/// The rank whose run holds `id` (0 <= id < rank_offsets.back()).
inline int owner_of(std::span<const std::int64_t> rank_offsets, std::int64_t id) {
  return int(std::upper_bound(rank_offsets.begin(), rank_offsets.end(), id) -
             rank_offsets.begin()) -
         1;
}

} // namespace texsim::par
