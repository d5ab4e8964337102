#pragma once
/// Graph partition by Scotch's sequential multilevel strategy, computed on rank 0 and broadcast:
/// a pure function of the graph and the number of parts. PT-Scotch (through PETSc
/// MatPartitioning) gave different partitions run to run whatever seed was set, which broke the
/// "same config, same rank count, same bytes" contract; Scotch in a context with its
/// deterministic and fixed-seed options does not, and cut fewer edges (docs/fem_rd.md).
#include "par/comm.hpp"

#include <cstdint>
#include <span>
#include <vector>

namespace texsim::par {

/// part[v] in [0, parts) for each vertex v of the undirected graph given in compressed rows
/// (row v is neighbors[offsets[v] .. offsets[v+1]), both directions of each edge present, no
/// self loops). Every rank passes the same graph; the result is the same on every rank and on
/// every run. Collective. Throws texsim::Error if Scotch fails or the graph exceeds its 32-bit
/// indices (2^31 vertices or adjacency entries).
/// The same partition computed on the calling rank alone (for a graph only that rank holds).
/// Not collective.
std::vector<int> scotch_graph_partition_serial(std::span<const std::int64_t> offsets,
                                               std::span<const std::int32_t> neighbors, int parts);

std::vector<int> scotch_graph_partition(const Comm& comm, std::span<const std::int64_t> offsets,
                                        std::span<const std::int32_t> neighbors, int parts);

} // namespace texsim::par
