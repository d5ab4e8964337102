#pragma once
/// The distinct appearance vectors of a feature grid. A nearest-distance search needs each vector
/// once: the exemplar's flat regions (a particle exemplar's background) repeat one vector at
/// hundreds of thousands of voxels, and a kd-tree cannot tell such exact ties apart by float
/// bounds, so it visited every one of them for each query whose nearest vector was among them
/// (40 s for neighbourhood_error at stride 2 on a 32^3 result of the 128^3 particles exemplar;
/// under 0.1 s over the 35 % of its vectors that are distinct).
#include "par/node_shared_array.hpp"
#include "vol/channel_grid.hpp"

#include <memory>

namespace texsim::pipelines::solid_synthesis {

/// One row per distinct bit pattern among the voxels of `features`, in increasing order of the
/// patterns compared bytewise, as a count x 1 x 1 grid with the same channels: the least distance
/// from any query to its rows is the least distance to the voxels of `features`.
vol::ChannelGrid distinct_feature_rows(const vol::ChannelGrid& features);

/// The same rows held once per node: each node's first rank finds them (with a private index of
/// 4 bytes per voxel of `features`) and writes them into the node's window. Collective over
/// layout->world.
vol::ChannelGrid distinct_feature_rows(const vol::ChannelGrid& features,
                                       std::shared_ptr<const par::NodeLayout> layout);

} // namespace texsim::pipelines::solid_synthesis
