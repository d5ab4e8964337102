#include "pipelines/solid_synthesis/distinct_features.hpp"

#include "core/error.hpp"
#include "par/collective.hpp"

#include <mpi.h>

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <numeric>
#include <span>
#include <vector>

namespace texsim::pipelines::solid_synthesis {
namespace {

/// The voxels of `features` whose row is the first of its bit pattern, in increasing order of the
/// patterns (bytewise: ties are exact equality of the stored floats, so no two rows merge that a
/// distance could tell apart).
std::vector<std::int32_t> first_of_each_pattern(const vol::ChannelGrid& features) {
  TEXSIM_VERIFY(features.voxel_count() <= std::size_t(INT32_MAX),
                "distinct_feature_rows: more voxels than 32-bit ids hold");
  const std::size_t row_bytes = std::size_t(features.channels()) * sizeof(float);
  const float* values = features.data().data();
  const auto row = [&](std::int32_t v) { return values + std::size_t(v) * features.channels(); };
  std::vector<std::int32_t> order(features.voxel_count());
  std::iota(order.begin(), order.end(), 0);
  // Ties broken by voxel id keep the sort deterministic whatever std::sort does with equals.
  std::sort(order.begin(), order.end(), [&](std::int32_t a, std::int32_t b) {
    const int c = std::memcmp(row(a), row(b), row_bytes);
    return c != 0 ? c < 0 : a < b;
  });
  const auto last = std::unique(order.begin(), order.end(), [&](std::int32_t a, std::int32_t b) {
    return std::memcmp(row(a), row(b), row_bytes) == 0;
  });
  order.erase(last, order.end());
  return order;
}

void copy_rows(const vol::ChannelGrid& features, std::span<const std::int32_t> voxels,
               std::span<float> out) {
  const auto channels = std::size_t(features.channels());
  for (std::size_t r = 0; r < voxels.size(); ++r) {
    const auto source = features.voxel(std::size_t(voxels[r]));
    std::copy(source.begin(), source.end(), out.begin() + std::ptrdiff_t(r * channels));
  }
}

vol::Dims row_dims(std::size_t rows) {
  return {int(rows), 1, 1};
}

} // namespace

vol::ChannelGrid distinct_feature_rows(const vol::ChannelGrid& features) {
  const auto voxels = first_of_each_pattern(features);
  vol::ChannelGrid rows(row_dims(voxels.size()), features.channels());
  copy_rows(features, voxels, rows.data());
  return rows;
}

vol::ChannelGrid distinct_feature_rows(const vol::ChannelGrid& features,
                                       std::shared_ptr<const par::NodeLayout> layout) {
  std::vector<std::int32_t> voxels;
  par::run_collectively(layout->world, [&] {
    if (layout->node.rank == 0)
      voxels = first_of_each_pattern(features);
  });
  // Every node finds the same count; its other ranks learn it from the node's first rank.
  std::int64_t count = std::int64_t(voxels.size());
  MPI_Bcast(&count, 1, MPI_INT64_T, 0, layout->node.raw);
  const auto channels = std::size_t(features.channels());
  par::NodeSharedBytes bytes(layout, std::size_t(count) * channels * sizeof(float));
  if (layout->node.rank == 0)
    copy_rows(features, voxels,
              {reinterpret_cast<float*>(bytes.bytes().data()), std::size_t(count) * channels});
  bytes.synchronise();
  return vol::ChannelGrid(row_dims(std::size_t(count)), features.channels(),
                          par::NodeSharedArray<float>(std::move(bytes)));
}

} // namespace texsim::pipelines::solid_synthesis
