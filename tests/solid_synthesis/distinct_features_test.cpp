#include "pipelines/solid_synthesis/distinct_features.hpp"

#include "core/rng.hpp"
#include "par/comm.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <set>
#include <vector>

namespace texsim::pipelines::solid_synthesis {
namespace {

std::vector<float> row_of(const vol::ChannelGrid& grid, std::size_t v) {
  const auto values = grid.voxel(v);
  return {values.begin(), values.end()};
}

/// A grid whose rows are mostly a few repeated vectors (a flat region) plus some random ones,
/// with -0.0 and 0.0 side by side: equal values but different bits.
vol::ChannelGrid tie_heavy_features(int channels) {
  const CounterRng rng(5, 0);
  vol::ChannelGrid features({9, 8, 7}, channels);
  for (std::size_t v = 0; v < features.voxel_count(); ++v)
    for (int c = 0; c < channels; ++c) {
      const double u = rng.uniform(v * 64 + std::size_t(c), 1);
      const float flat = v % 3 == 0 ? -0.0f : (v % 3 == 1 ? 0.0f : 0.25f * float(c));
      features.voxel(v)[c] = v % 5 == 0 ? float(u) : flat;
    }
  return features;
}

/// Every input row appears among the distinct rows, and they hold no two equal bit patterns:
/// checked against a std::set of the rows (floats compared by value would merge -0.0 and 0.0).
void expect_distinct_rows_of(const vol::ChannelGrid& features, const vol::ChannelGrid& rows) {
  const auto bits = [](const std::vector<float>& row) {
    std::vector<std::uint32_t> out(row.size());
    std::memcpy(out.data(), row.data(), row.size() * sizeof(float));
    return out;
  };
  std::set<std::vector<std::uint32_t>> expected, found;
  for (std::size_t v = 0; v < features.voxel_count(); ++v)
    expected.insert(bits(row_of(features, v)));
  for (std::size_t r = 0; r < rows.voxel_count(); ++r)
    found.insert(bits(row_of(rows, r)));
  EXPECT_EQ(rows.voxel_count(), expected.size());
  EXPECT_EQ(found, expected);
  EXPECT_EQ(rows.channels(), features.channels());
}

TEST(DistinctFeatures, EachBitPatternOnce) {
  for (const int channels : {1, 3, 8}) {
    const auto features = tie_heavy_features(channels);
    const auto rows = distinct_feature_rows(features);
    expect_distinct_rows_of(features, rows);
    // The flat rows collapse: 3 patterns plus one per random row (every fifth voxel).
    EXPECT_LE(rows.voxel_count(), 3 + features.voxel_count() / 5 + 1) << channels;
  }
}

TEST(DistinctFeatures, NodeSharedRowsEqualTheSerialRows) {
  const auto features = tie_heavy_features(8);
  const auto serial = distinct_feature_rows(features);
  for (const int ranks_per_node : {1, 2}) {
    const auto shared =
        distinct_feature_rows(features, par::NodeLayout::make(par::world(), ranks_per_node));
    EXPECT_TRUE(shared.node_shared());
    ASSERT_EQ(shared.voxel_count(), serial.voxel_count());
    for (std::size_t r = 0; r < serial.voxel_count(); ++r)
      ASSERT_EQ(row_of(shared, r), row_of(serial, r)) << "row " << r;
  }
}

} // namespace
} // namespace texsim::pipelines::solid_synthesis
