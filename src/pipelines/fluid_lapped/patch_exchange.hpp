#pragma once
/// Moving patches between ranks. A patch has a variable number of vertices and triangles, so it
/// travels as flat records (one per vertex, one per triangle) and is put together again on
/// arrival; every receiving rank holds its patches sorted by id.
#include "par/comm.hpp"
#include "pipelines/fluid_lapped/patch.hpp"

#include <span>
#include <vector>

namespace texsim::pipelines::fluid_lapped {

/// Sends patch i to rank destination[i] (destination.size() == patches.size()); returns the
/// patches this rank receives, sorted by id. Collective.
std::vector<Patch> exchange_patches(const par::Comm& comm, std::span<const Patch> patches,
                                    std::span<const int> destination);

/// The rank of every patch when all patches are split by a Morton curve over their centres
/// (the mean of their vertex positions): each rank gets a compact region of the surface, and the
/// split depends on the patches alone, not on where they were. Returns one rank per local patch.
/// Collective.
std::vector<int> morton_destinations(const par::Comm& comm, std::span<const Patch> patches);

/// The rank of every local patch when the patches of all ranks, in id order, are cut into
/// comm.size contiguous runs of nearly equal vertex counts: checkpoints are written in id order.
/// Collective.
std::vector<int> id_order_destinations(const par::Comm& comm, std::span<const Patch> patches);

} // namespace texsim::pipelines::fluid_lapped
