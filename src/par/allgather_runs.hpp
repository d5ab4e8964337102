#pragma once
/// Completing an array replicated on every rank whose ranks each computed their own run of it
/// (par/id_runs.hpp): one MPI_Allgatherv in place.
#include "par/comm.hpp"

#include <mpi.h>

#include <cstdint>
#include <span>
#include <vector>

namespace texsim::par {

/// The rank offsets of runs of `count` items per rank, in rank order (comm.size + 1 entries, an
/// O(ranks) table). Collective.
std::vector<std::int64_t> run_offsets(const Comm& comm, std::int64_t count);

/// `values` holds rank_offsets.back() elements of `width` items of `type` each, and this rank's
/// run [rank_offsets[r], rank_offsets[r + 1]) is filled in; on return every run is, on every rank.
/// Throws when a run or the array has more than 2^31 - 1 items (MPI's int counts). Collective.
void allgather_runs(const Comm& comm, std::span<const std::int64_t> rank_offsets, void* values,
                    int width, MPI_Datatype type);

} // namespace texsim::par
