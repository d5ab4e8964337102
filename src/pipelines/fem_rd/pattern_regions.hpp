#pragma once
/// Counting the spots of a pattern: connected regions (through mesh edges) of vertices whose value
/// is above the mean. Spots of Fig. 3 are such regions; their number grows with s.
#include "geom/distributed_mesh.hpp"

#include <span>

namespace texsim::pipelines::fem_rd {

struct RegionCount {
  int regions = 0;          ///< connected regions above the mean
  double threshold = 0;     ///< the mean value
  double mean_vertices = 0; ///< vertices per region
};

/// `owned` holds this rank's values. Each region is labelled by its smallest global vertex id:
/// labels are settled on each rank's owned vertices and ghosts and exchanged with the neighbours
/// until no label changes (one round per partition boundary a region crosses). Collective.
RegionCount count_regions_above_mean(const geom::DistributedMesh& mesh,
                                     std::span<const double> owned);

} // namespace texsim::pipelines::fem_rd
