#pragma once
/// The checksum stored with every checkpoint dataset. It is the sum (mod 2^64) over all scalars of
/// splitmix64-mixes of (global scalar index, raw bits of the scalar), so it does not depend on how
/// the dataset is split across ranks or in which order the blocks are summed: a checkpoint written
/// at 3 ranks and one written at 1 rank from the same data carry the same checksum.
#include "par/comm.hpp"

#include <cstddef>
#include <cstdint>

namespace texsim::io {

/// This block's share of the checksum: `count` scalars of `scalar_size` bytes (1..8) at `values`,
/// the first of which has global scalar index `first_index` (element offset times components).
/// Not collective.
std::uint64_t checksum_block(const void* values, std::size_t count, std::size_t scalar_size,
                             std::uint64_t first_index);

/// The sum of every rank's `local` share, identical on all ranks. Collective.
std::uint64_t checksum_sum_over_ranks(const par::Comm& comm, std::uint64_t local);

} // namespace texsim::io
