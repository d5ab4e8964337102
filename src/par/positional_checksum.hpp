#pragma once
/// A checksum of an array split over ranks that does not depend on the split: the sum (mod 2^64)
/// over all scalars of splitmix64-mixes of (global scalar index, raw bits of the scalar), so the
/// blocks may be summed in any order and a dataset written at 3 ranks carries the checksum of the
/// same dataset written at 1. Stored with every checkpoint dataset (io/checkpoint_format.hpp) and
/// the content-derived UUID of a .vdb written in parallel (vol/parallel_vdb_writer.hpp).
#include "par/comm.hpp"

#include <cstddef>
#include <cstdint>

namespace texsim::par {

/// This block's share of the checksum: `count` scalars of `scalar_size` bytes (1..8) at `values`,
/// the first of which has global scalar index `first_index` (element offset times components).
/// Not collective.
std::uint64_t checksum_block(const void* values, std::size_t count, std::size_t scalar_size,
                             std::uint64_t first_index);

/// The sum of every rank's `local` share, identical on all ranks. Collective.
std::uint64_t checksum_sum_over_ranks(const par::Comm& comm, std::uint64_t local);

} // namespace texsim::par
