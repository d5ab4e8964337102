#include "core/rng.hpp"
#include "geom/aabb_tree.hpp"
#include "geom/generators.hpp"

#include <Eigen/Geometry>
#include <gtest/gtest.h>

#include <cmath>

namespace texsim::geom {
namespace {

TEST(AabbTree, ClosestPointsOnSphereLieOnTheirTriangleAndNearTheSphere) {
  const auto mesh = icosphere(4);
  const AabbTree tree(mesh);
  const CounterRng rng(7, 1);
  for (std::uint64_t i = 0; i < 200; ++i) {
    const Vec3 direction =
        Vec3(rng.normal(i, 0, 0), rng.normal(i, 0, 1), rng.normal(i, 0, 2)).normalized();
    const double radius = rng.uniform(0.3, 2.0, i, 1);
    const Vec3 query = radius * direction;
    const auto hit = tree.closest_point(query);
    // Level 4 triangles sit at most ~1e-3 inside the unit sphere.
    EXPECT_NEAR(hit.distance, std::abs(radius - 1.0), 2e-3);
    EXPECT_NEAR(hit.distance, (hit.point - query).norm(), 1e-14);
    // The point lies on the reported triangle: barycentric coordinates in [0, 1], in its plane.
    const auto& tri = mesh.triangles[hit.triangle];
    const Vec3 a = mesh.positions[tri[0]], b = mesh.positions[tri[1]], c = mesh.positions[tri[2]];
    const Vec3 normal = (b - a).cross(c - a);
    EXPECT_NEAR(normal.normalized().dot(hit.point - a), 0.0, 1e-12);
    const double total = normal.squaredNorm();
    const double wa = normal.dot((c - b).cross(hit.point - b)) / total;
    const double wb = normal.dot((a - c).cross(hit.point - c)) / total;
    EXPECT_GE(wa, -1e-12);
    EXPECT_GE(wb, -1e-12);
    EXPECT_LE(wa + wb, 1.0 + 1e-12);
    // No vertex is closer than the closest surface point (brute force).
    for (const auto& p : mesh.positions) {
      ASSERT_LE(hit.distance, (p - query).norm() + 1e-12);
    }
  }
  const auto on_vertex = tree.closest_point(mesh.positions[17]);
  EXPECT_LT(on_vertex.distance, 1e-12);
}

} // namespace
} // namespace texsim::geom
