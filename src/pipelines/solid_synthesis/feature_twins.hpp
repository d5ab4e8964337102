#pragma once
/// Voxels with identical features (every channel equal as floats), grouped. They are the exact
/// ties of the similarity sets at distance 0: nothing can come before a voxel's twins, and among
/// them the lower index wins. A flat-coloured exemplar (the background of `particles`, the
/// mortar of bricks, a lattice) has groups of thousands to millions of twins, which the kd-tree
/// visits one by one and the scan compares with every voxel; its twins decide most sets at once.
#include "par/node_shared_array.hpp"
#include "vol/channel_grid.hpp"

#include <cstdint>
#include <memory>
#include <span>
#include <vector>

namespace texsim::pipelines::solid_synthesis {

class FeatureTwins {
public:
  /// Sorts the voxels by their features (channel by channel, then by index): O(N log N), on
  /// layout->world's rank 0; held once per node (12 bytes a voxel, which every rank would
  /// otherwise hold). Collective over layout->world.
  FeatureTwins(const vol::ChannelGrid& features, std::shared_ptr<const par::NodeLayout> layout);

  /// The voxels whose features equal `voxel`'s, itself included, in increasing index.
  std::span<const std::int32_t> of(std::int32_t voxel) const {
    const std::int32_t group = group_of_voxel_[static_cast<std::size_t>(voxel)];
    const auto begin = static_cast<std::size_t>(group_begin_[static_cast<std::size_t>(group)]);
    const auto end = static_cast<std::size_t>(group_begin_[static_cast<std::size_t>(group) + 1]);
    return sorted_.subspan(begin, end - begin);
  }

  /// Voxels that have at least one twin.
  std::int64_t tied_voxels() const;

private:
  struct Groups;
  struct SharedGroups;

  std::shared_ptr<const void> storage_;          ///< the arrays below point into it
  std::span<const std::int32_t> sorted_;         ///< voxels by (features, index)
  std::span<const std::int32_t> group_begin_;    ///< per group, its first position; then the end
  std::span<const std::int32_t> group_of_voxel_; ///< per voxel
};

} // namespace texsim::pipelines::solid_synthesis
