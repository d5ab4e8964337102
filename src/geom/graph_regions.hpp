#pragma once
/// Connected regions of a graph restricted to marked nodes (spots and stripes of a pattern are the
/// regions of nodes above a threshold).
#include "geom/mesh_topology.hpp"

#include <cstdint>
#include <span>
#include <vector>

namespace texsim::geom {

/// label[i] = region index (0, 1, ... in order of each region's smallest node) for marked nodes,
/// -1 for the others. `neighbors` is symmetric. Serial.
std::vector<std::int32_t> label_regions(const CsrAdjacency& neighbors,
                                        std::span<const char> marked);

} // namespace texsim::geom
