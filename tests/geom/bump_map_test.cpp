#include "geom/bump_map.hpp"

#include "core/error.hpp"
#include "geom/generators.hpp"
#include "geom/mesh_measures.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

namespace texsim::geom {
namespace {

/// (n + 1) x (n + 1) vertices over [0, 1]^2 at z = 0, each cell split into two triangles
/// (counter-clockwise seen from +z).
TriangleMesh flat_grid(int n) {
  TriangleMesh mesh;
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i)
      mesh.positions.emplace_back(double(i) / n, double(j) / n, 0.0);
  const auto id = [n](int i, int j) { return std::int32_t(j * (n + 1) + i); };
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      mesh.triangles.push_back({id(i, j), id(i + 1, j), id(i + 1, j + 1)});
      mesh.triangles.push_back({id(i, j), id(i + 1, j + 1), id(i, j + 1)});
    }
  return mesh;
}

TEST(BumpMap, FlatGridWithHeightXTiltsThePlane) {
  const int n = 16;
  const auto mesh = flat_grid(n);
  std::vector<double> height(mesh.positions.size());
  std::transform(mesh.positions.begin(), mesh.positions.end(), height.begin(),
                 [](const Vec3& p) { return p.x(); });
  const double scale = 0.3;
  const auto bumped = bump_map(mesh, height, scale);
  ASSERT_EQ(bumped.positions.size(), mesh.positions.size());
  ASSERT_EQ(bumped.normals.size(), mesh.positions.size());
  const Vec3 tilted = Vec3(-scale, 0.0, 1.0).normalized();
  for (std::size_t v = 0; v < mesh.positions.size(); ++v) {
    const Vec3& p = mesh.positions[v];
    EXPECT_NEAR((bumped.positions[v] - Vec3(p.x(), p.y(), scale * p.x())).norm(), 0.0, 1e-15)
        << "vertex " << v;
    // The displaced surface is the plane z = scale x, so every vertex normal (interior and
    // boundary) is its unit normal.
    EXPECT_NEAR((bumped.normals[v] - tilted).norm(), 0.0, 1e-14) << "vertex " << v;
  }
}

TEST(BumpMap, NegativeScaleAndZeroHeightLeaveTheRightThings) {
  const auto mesh = flat_grid(8);
  std::vector<double> height(mesh.positions.size());
  for (std::size_t v = 0; v < height.size(); ++v)
    height[v] = mesh.positions[v].y();
  const auto down = bump_map(mesh, height, -0.5);
  const Vec3 tilted = Vec3(0.0, 0.5, 1.0).normalized(); // plane z = -0.5 y
  for (std::size_t v = 0; v < height.size(); ++v) {
    EXPECT_NEAR(down.positions[v].z(), -0.5 * mesh.positions[v].y(), 1e-15);
    EXPECT_NEAR((down.normals[v] - tilted).norm(), 0.0, 1e-14);
  }
  const auto flat = bump_map(mesh, height, 0.0);
  for (std::size_t v = 0; v < height.size(); ++v) {
    EXPECT_EQ(flat.positions[v], mesh.positions[v]);
    EXPECT_NEAR((flat.normals[v] - Vec3(0, 0, 1)).norm(), 0.0, 1e-15);
  }
}

TEST(BumpMap, SphereWithConstantHeightGrowsAndKeepsRadialNormals) {
  const double radius = 2.0, h = 0.5, scale = 0.4;
  const auto mesh = icosphere(4, radius);
  const auto normals = vertex_normals(mesh);
  const std::vector<double> height(mesh.positions.size(), h);
  const auto bumped = bump_map(mesh, height, scale);
  double worst_radius = 0.0, worst_radial = 0.0, mesh_radial = 0.0, worst_change = 0.0;
  for (std::size_t v = 0; v < mesh.positions.size(); ++v) {
    const Vec3 radial = mesh.positions[v].normalized();
    worst_radius =
        std::max(worst_radius, std::abs(bumped.positions[v].norm() - (radius + scale * h)));
    worst_radial = std::max(worst_radial, (bumped.normals[v] - radial).norm());
    mesh_radial = std::max(mesh_radial, (normals[v] - radial).norm());
    worst_change = std::max(worst_change, (bumped.normals[v] - normals[v]).norm());
  }
  std::printf("icosphere level 4: radius error %.2e, normals off radial %.2e (mesh's own %.2e), "
              "changed by %.2e\n",
              worst_radius, worst_radial, mesh_radial, worst_change);
  // The area-weighted vertex normals of an icosphere are radial only to within a small angle
  // (mesh_radial); the displaced vertices lie on the sphere of radius r + scale h to second
  // order in that angle, and the grown sphere is (nearly) the scaled mesh, so its normals are as
  // radial as the original ones and barely differ from them.
  EXPECT_LT(worst_radius, 1e-5);
  EXPECT_LT(worst_radial, 1.05 * mesh_radial);
  EXPECT_LT(mesh_radial, 1e-2);
  EXPECT_LT(worst_change, 1e-3);
}

TEST(BumpMap, RejectsMismatchedHeights) {
  const auto mesh = flat_grid(2);
  EXPECT_THROW(bump_map(mesh, std::vector<double>(3, 0.0), 1.0), Error);
  EXPECT_THROW(bump_map(mesh, std::vector<double>(9, 0.0), std::nan("")), Error);
}

} // namespace
} // namespace texsim::geom
