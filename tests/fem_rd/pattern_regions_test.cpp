// The distributed region count equals the serial count of connected regions above the mean on the
// whole surface, for patterns whose regions cross partition boundaries many times (a banded
// field winding round the sphere, and spotty noise), at 1, 2 and 3 ranks.
#include "core/rng.hpp"
#include "geom/generators.hpp"
#include "geom/graph_regions.hpp"
#include "pipelines/fem_rd/pattern_regions.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <numeric>

namespace texsim::pipelines::fem_rd {
namespace {

int serial_regions(const geom::TriangleMesh& surface, const std::vector<double>& values) {
  const double mean = std::accumulate(values.begin(), values.end(), 0.0) / double(values.size());
  std::vector<char> above(values.size());
  for (std::size_t v = 0; v < values.size(); ++v)
    above[v] = values[v] > mean;
  const auto labels = geom::label_regions(geom::MeshTopology(surface).vertex_neighbors(), above);
  return 1 + *std::max_element(labels.begin(), labels.end());
}

void check(const std::function<double(const geom::Vec3&, std::int64_t)>& field) {
  const auto sphere = geom::icosphere(5);
  std::vector<double> whole(sphere.positions.size());
  for (std::size_t v = 0; v < whole.size(); ++v)
    whole[v] = field(sphere.positions[v], std::int64_t(v));
  const int expected = serial_regions(sphere, whole);
  ASSERT_GT(expected, 3);
  for (const auto method : {geom::PartitionMethod::kMorton, geom::PartitionMethod::kScotch}) {
    const geom::DistributedMesh mesh(par::world(), sphere, method);
    std::vector<double> owned(std::size_t(mesh.owned_count()));
    for (std::size_t v = 0; v < owned.size(); ++v)
      owned[v] = whole[std::size_t(mesh.input_id()[v])];
    const auto count = count_regions_above_mean(mesh, owned);
    EXPECT_EQ(count.regions, expected);
    EXPECT_NEAR(count.threshold,
                std::accumulate(whole.begin(), whole.end(), 0.0) / double(whole.size()), 1e-12);
  }
}

TEST(PatternRegions, SpiralBandsCountAsOnTheWholeSurface) {
  // Six bands twisted round the axis, kept apart at the poles: long thin regions crossing every
  // partition.
  check([](const geom::Vec3& p, std::int64_t) {
    return std::abs(p.z()) < 0.8 ? std::sin(6.0 * std::atan2(p.y(), p.x()) + 9.0 * p.z()) : -1.0;
  });
}

TEST(PatternRegions, NoiseSpotsCountAsOnTheWholeSurface) {
  const CounterRng rng(5, 2);
  check([&](const geom::Vec3& p, std::int64_t v) {
    return std::sin(7.0 * p.x()) * std::cos(5.0 * p.y()) + 0.3 * rng.uniform(-1, 1, v, 0);
  });
}

} // namespace
} // namespace texsim::pipelines::fem_rd
