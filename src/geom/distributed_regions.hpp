#pragma once
/// The connected regions of the marked nodes of a graph split over ranks (the spots and stripes of
/// a pattern on a distributed surface), each labelled by the smallest global id among its nodes,
/// whatever the partition.
#include "geom/mesh_topology.hpp"
#include "par/comm.hpp"

#include <cstdint>
#include <functional>
#include <span>
#include <vector>

namespace texsim::geom {

/// Fills the ghost entries of a per-local-node array from their owners. Collective.
using GhostUpdate = std::function<void(std::span<double>)>;

/// Every rank holds `owned_count` owned nodes and then ghosts (and possibly more halo nodes,
/// never marked), with `local_neighbors` a symmetric adjacency over these local nodes that
/// includes every edge between two of them the global graph has, and `global_ids` the nodes'
/// global ids (below 2^53). Labels settle on each rank's local components, then reach the other
/// ranks through the ghosts, until no label changes: one round per partition boundary a region
/// crosses. Returns each local node's label: the smallest global id of its region, -1 for
/// unmarked nodes. Collective.
std::vector<std::int64_t>
label_regions_across_ranks(const par::Comm& comm, const CsrAdjacency& local_neighbors,
                           std::span<const char> marked, std::span<const std::int64_t> global_ids,
                           std::int32_t owned_count, const GhostUpdate& update_ghosts);

} // namespace texsim::geom
