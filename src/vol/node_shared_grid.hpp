#pragma once
/// Building a read-only ChannelGrid held once per node (par::NodeSharedArray) plane by plane: the
/// node's ranks each write a share of the z-planes, so the work and the page touches are split
/// among them and no rank ever holds a private copy of the whole grid.
#include "par/node_shared_array.hpp"
#include "vol/channel_grid.hpp"

#include <algorithm>
#include <cstddef>
#include <memory>
#include <span>

namespace texsim::vol {

/// A node-shared grid of `dims` x `channels` whose planes [z_begin, z_end) are written by
/// `fill_planes(z_begin, z_end, values)` (`values`: those planes, x fastest). Each rank of a node
/// fills a contiguous share of the planes; `fill_planes` must not throw (a rank that threw would
/// leave its node waiting). Collective over layout->world.
template <class FillPlanes>
ChannelGrid node_shared_grid(const std::shared_ptr<const par::NodeLayout>& layout, Dims dims,
                             int channels, FillPlanes fill_planes) {
  const std::size_t plane = static_cast<std::size_t>(dims.nx) * static_cast<std::size_t>(dims.ny) *
                            static_cast<std::size_t>(channels);
  const std::size_t granule = std::max<std::size_t>(plane, 1); // an empty grid has no planes
  auto values = par::NodeSharedArray<float>::filled(
      layout, plane * static_cast<std::size_t>(dims.nz),
      [&](std::span<float> all, std::size_t begin, std::size_t end) {
        fill_planes(static_cast<int>(begin / granule), static_cast<int>(end / granule),
                    all.subspan(begin, end - begin));
      },
      granule);
  return ChannelGrid(dims, channels, std::move(values));
}

} // namespace texsim::vol
