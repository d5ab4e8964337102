#include "pipelines/solid_synthesis/feature_twins.hpp"

#include "core/error.hpp"

#include <algorithm>
#include <limits>
#include <numeric>

namespace texsim::pipelines::solid_synthesis {

FeatureTwins::FeatureTwins(const vol::ChannelGrid& features) {
  const std::size_t voxels = features.voxel_count();
  TEXSIM_VERIFY(voxels <= static_cast<std::size_t>(std::numeric_limits<std::int32_t>::max()),
                "feature twins: " << voxels << " voxels do not fit 32-bit indices");
  const int channels = features.channels();
  const float* values = features.data().data();
  const auto row = [&](std::int32_t v) { return values + static_cast<std::size_t>(v) * channels; };
  // Float comparison, not bytes: -0 and +0 are the same feature (their distance is 0).
  const auto equal = [&](std::int32_t a, std::int32_t b) {
    return std::equal(row(a), row(a) + channels, row(b));
  };
  sorted_.resize(voxels);
  std::iota(sorted_.begin(), sorted_.end(), 0);
  std::sort(sorted_.begin(), sorted_.end(), [&](std::int32_t a, std::int32_t b) {
    const auto [pa, pb] = std::mismatch(row(a), row(a) + channels, row(b));
    return pa == row(a) + channels ? a < b : *pa < *pb;
  });
  group_of_voxel_.resize(voxels);
  for (std::size_t i = 0; i < voxels; ++i) {
    if (i == 0 || !equal(sorted_[i - 1], sorted_[i]))
      group_begin_.push_back(static_cast<std::int32_t>(i));
    group_of_voxel_[static_cast<std::size_t>(sorted_[i])] =
        static_cast<std::int32_t>(group_begin_.size() - 1);
  }
  group_begin_.push_back(static_cast<std::int32_t>(voxels));
  for (std::size_t g = 0; g + 1 < group_begin_.size(); ++g) {
    const std::int64_t size = group_begin_[g + 1] - group_begin_[g];
    tied_voxels_ += size > 1 ? size : 0;
  }
}

} // namespace texsim::pipelines::solid_synthesis
