#include "pipelines/solid_synthesis/feature_twins.hpp"

#include "core/error.hpp"
#include "par/collective.hpp"

#include <algorithm>
#include <limits>
#include <numeric>
#include <optional>

namespace texsim::pipelines::solid_synthesis {

/// The groups as one rank sorts them.
struct FeatureTwins::Groups {
  std::vector<std::int32_t> sorted;
  std::vector<std::int32_t> group_begin;
  std::vector<std::int32_t> group_of_voxel;

  Groups() = default;
  explicit Groups(const vol::ChannelGrid& features) {
    const std::size_t voxels = features.voxel_count();
    TEXSIM_VERIFY(voxels <= static_cast<std::size_t>(std::numeric_limits<std::int32_t>::max()),
                  "feature twins: " << voxels << " voxels do not fit 32-bit indices");
    const int channels = features.channels();
    const float* values = features.data().data();
    const auto row = [&](std::int32_t v) {
      return values + static_cast<std::size_t>(v) * channels;
    };
    // Float comparison, not bytes: -0 and +0 are the same feature (their distance is 0).
    const auto equal = [&](std::int32_t a, std::int32_t b) {
      return std::equal(row(a), row(a) + channels, row(b));
    };
    sorted.resize(voxels);
    std::iota(sorted.begin(), sorted.end(), 0);
    std::sort(sorted.begin(), sorted.end(), [&](std::int32_t a, std::int32_t b) {
      const auto [pa, pb] = std::mismatch(row(a), row(a) + channels, row(b));
      return pa == row(a) + channels ? a < b : *pa < *pb;
    });
    group_of_voxel.resize(voxels);
    for (std::size_t i = 0; i < voxels; ++i) {
      if (i == 0 || !equal(sorted[i - 1], sorted[i]))
        group_begin.push_back(static_cast<std::int32_t>(i));
      group_of_voxel[static_cast<std::size_t>(sorted[i])] =
          static_cast<std::int32_t>(group_begin.size() - 1);
    }
    group_begin.push_back(static_cast<std::int32_t>(voxels));
  }
};

/// The groups held once per node.
struct FeatureTwins::SharedGroups {
  par::NodeSharedArray<std::int32_t> sorted;
  par::NodeSharedArray<std::int32_t> group_begin;
  par::NodeSharedArray<std::int32_t> group_of_voxel;
};

FeatureTwins::FeatureTwins(const vol::ChannelGrid& features,
                           std::shared_ptr<const par::NodeLayout> layout) {
  // Rank 0 sorts; its vectors are freed once they are in the node windows.
  std::optional<Groups> built;
  par::run_collectively(layout->world, [&] {
    if (layout->world.rank == 0)
      built.emplace(features);
  });
  const Groups empty_groups;
  const Groups& source = built ? *built : empty_groups;
  using Shared = par::NodeSharedArray<std::int32_t>;
  auto shared = std::make_shared<const SharedGroups>(SharedGroups{
      Shared::from_root(layout, source.sorted), Shared::from_root(layout, source.group_begin),
      Shared::from_root(layout, source.group_of_voxel)});
  built.reset();
  sorted_ = shared->sorted.values();
  group_begin_ = shared->group_begin.values();
  group_of_voxel_ = shared->group_of_voxel.values();
  storage_ = std::move(shared);
}

std::int64_t FeatureTwins::tied_voxels() const {
  std::int64_t tied = 0;
  for (std::size_t g = 0; g + 1 < group_begin_.size(); ++g) {
    const std::int64_t size = group_begin_[g + 1] - group_begin_[g];
    tied += size > 1 ? size : 0;
  }
  return tied;
}

} // namespace texsim::pipelines::solid_synthesis
