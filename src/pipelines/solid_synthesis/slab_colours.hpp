#pragma once
/// The colours a synthesized volume S shows: the exemplar's colour at each voxel's exemplar
/// coordinate, for the outputs and the quality measures.
#include "pipelines/solid_synthesis/coordinate_slab.hpp"
#include "vol/channel_grid.hpp"

#include <span>

namespace texsim::pipelines::solid_synthesis {

/// The exemplar's colour at coordinate c (inside the exemplar).
inline std::span<const float> colour_at(const vol::ChannelGrid& exemplar, const Coord& c) {
  return exemplar.voxel(exemplar.index(c.x, c.y, c.z));
}

/// The colours of planes [k_first, k_first + planes) of the slab (owned or halo), x in [0, nx)
/// and y in [0, ny) (periodic beyond the level's size), x fastest. OpenMP over planes.
vol::ChannelGrid coloured_planes(const CoordinateSlab& slab, const vol::ChannelGrid& exemplar,
                                 int nx, int ny, int k_first, int planes);

} // namespace texsim::pipelines::solid_synthesis
