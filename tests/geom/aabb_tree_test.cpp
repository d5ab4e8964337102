#include "core/rng.hpp"
#include "geom/aabb_tree.hpp"
#include "geom/generators.hpp"
#include "geom/mesh_measures.hpp"

#include <Eigen/Geometry>
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <optional>

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

/// The nearest line crossing by brute force, written apart from the tree's Moller-Trumbore test:
/// the crossing of each triangle's plane, kept when its barycentric weights (geom's projection
/// formula) are >= -1e-12.
struct BruteForceHit {
  double t;
  std::int32_t triangle;
};

std::optional<BruteForceHit> brute_force_line_hit(const TriangleMesh& mesh, const Vec3& origin,
                                                  const Vec3& direction) {
  std::optional<BruteForceHit> best;
  for (std::int32_t t = 0; t < mesh.num_triangles(); ++t) {
    const auto& tri = mesh.triangles[t];
    const Vec3 a = mesh.positions[tri[0]], b = mesh.positions[tri[1]], c = mesh.positions[tri[2]];
    const Vec3 normal = (b - a).cross(c - a);
    const double across = normal.dot(direction);
    if (std::abs(across) <= 1e-12 * normal.norm() * direction.norm())
      continue;
    const double param = normal.dot(a - origin) / across;
    const auto w = barycentric_weights(a, b, c, origin + param * direction);
    if (w[0] < -1e-12 || w[1] < -1e-12 || w[2] < -1e-12)
      continue;
    if (!best || std::abs(param) < std::abs(best->t))
      best = BruteForceHit{param, t};
  }
  return best;
}

TEST(AabbTree, NearestLineHitMatchesBruteForceOnNoisySphereBothWaysAndMisses) {
  const auto mesh = noisy(icosphere(3), 0.03, 11);
  const AabbTree tree(mesh);
  const CounterRng rng(5, 2);
  int hits = 0, misses = 0, backward = 0;
  for (std::uint64_t i = 0; i < 400; ++i) {
    const Vec3 origin =
        rng.uniform(0.0, 2.5, i, 0) *
        Vec3(rng.normal(i, 1, 0), rng.normal(i, 1, 1), rng.normal(i, 1, 2)).normalized();
    const Vec3 direction =
        rng.uniform(0.2, 3.0, i, 2) *
        Vec3(rng.normal(i, 3, 0), rng.normal(i, 3, 1), rng.normal(i, 3, 2)).normalized();
    const auto expected = brute_force_line_hit(mesh, origin, direction);
    const auto hit = tree.nearest_line_hit(origin, direction);
    ASSERT_EQ(hit.has_value(), expected.has_value()) << "line " << i;
    if (!hit) {
      ++misses;
      continue;
    }
    ++hits;
    backward += expected->t < 0 ? 1 : 0;
    // The same crossing: the same triangle, or (a line through a shared edge) the same |t|.
    const double t_size = hit->distance / direction.norm();
    if (hit->triangle != expected->triangle)
      EXPECT_NEAR(t_size, std::abs(expected->t), 1e-9) << "line " << i;
    else
      EXPECT_NEAR(t_size, std::abs(expected->t), 1e-12 * (1 + t_size)) << "line " << i;
    EXPECT_NEAR((hit->point - (origin + expected->t * direction)).norm(), 0.0, 1e-9);
    EXPECT_NEAR(hit->distance, (hit->point - origin).norm(), 1e-12 * (1 + hit->distance));
  }
  // Lines through the sphere and past it, crossings on both sides of the origin.
  EXPECT_GT(hits, 200);
  EXPECT_GT(misses, 20);
  EXPECT_GT(backward, 50);
}

TEST(AabbTree, NearestLineHitTakesTheNearerSideAndMissesParallelLines) {
  const auto mesh = icosphere(3);
  const AabbTree tree(mesh);
  // From inside near the north pole: the pole is nearer than the south pole, either direction.
  for (const double sign : {1.0, -1.0}) {
    const auto hit = tree.nearest_line_hit(Vec3(0.01, 0.02, 0.8), Vec3(0, 0, sign * 2.0));
    ASSERT_TRUE(hit.has_value());
    EXPECT_GT(hit->point.z(), 0.9);
    EXPECT_NEAR(hit->distance, hit->point.z() - 0.8, 1e-12);
  }
  EXPECT_FALSE(tree.nearest_line_hit(Vec3(3, 0, 0), Vec3(0, 0, 1)).has_value());
  EXPECT_FALSE(tree.nearest_line_hit(Vec3(0, 0, 0), Vec3::Zero()).has_value());
  // A single triangle in the z = 0 plane: a line in that plane is parallel to it.
  TriangleMesh flat;
  flat.positions = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0)};
  flat.triangles = {{0, 1, 2}};
  const AabbTree flat_tree(flat);
  EXPECT_FALSE(flat_tree.nearest_line_hit(Vec3(-1, 0.2, 0), Vec3(1, 0, 0)).has_value());
  const auto through = flat_tree.nearest_line_hit(Vec3(0.2, 0.2, -3), Vec3(0, 0, 2));
  ASSERT_TRUE(through.has_value());
  EXPECT_EQ(through->triangle, 0);
  EXPECT_NEAR(through->distance, 3.0, 1e-15);
}

} // namespace
} // namespace texsim::geom
