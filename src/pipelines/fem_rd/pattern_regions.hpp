#pragma once
/// Counting the spots of a pattern: connected regions (through mesh edges) of vertices whose value
/// is above the mean. Spots of Fig. 3 are such regions; their number grows with s.
#include "geom/mesh_topology.hpp"

#include <span>

namespace texsim::pipelines::fem_rd {

struct RegionCount {
  int regions = 0;          ///< connected regions above the mean
  double threshold = 0;     ///< the mean value
  double mean_vertices = 0; ///< vertices per region
};

/// `values` in the topology's vertex order. Serial.
RegionCount count_regions_above_mean(const geom::MeshTopology& topology,
                                     std::span<const double> values);

} // namespace texsim::pipelines::fem_rd
