#include "pipelines/solid_synthesis/slab_colours.hpp"

#include <algorithm>

namespace texsim::pipelines::solid_synthesis {

vol::ChannelGrid coloured_planes(const CoordinateSlab& slab, const vol::ChannelGrid& exemplar,
                                 int nx, int ny, int k_first, int planes) {
  vol::ChannelGrid colours(vol::Dims{nx, ny, planes}, exemplar.channels());
#pragma omp parallel for schedule(static)
  for (int k = 0; k < planes; ++k)
    for (int j = 0; j < ny; ++j)
      for (int i = 0; i < nx; ++i) {
        const auto colour = colour_at(exemplar, slab.voxel(i, j, k_first + k));
        std::copy(colour.begin(), colour.end(), colours.voxel(colours.index(i, j, k)).begin());
      }
  return colours;
}

} // namespace texsim::pipelines::solid_synthesis
