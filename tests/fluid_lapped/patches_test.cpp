// Patches of Gagnon et al. 2021: the distortion metric and equations 1-3 against hand values; a
// patch on a flat grid is an isometry with p at (0.5, 0.5); a thin slab's far sheet stays out; a
// patch on a sphere is a disk; Poisson-disk centres keep their spacing and leave no gap.
#include "core/rng.hpp"
#include "geom/chart_segmentation.hpp"
#include "geom/generators.hpp"
#include "geom/mesh_measures.hpp"
#include "geom/poisson_disk_points.hpp"
#include "geom/random_surface_points.hpp"
#include "pipelines/fluid_lapped/patch_builder.hpp"
#include "pipelines/fluid_lapped/patch_distortion.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numeric>

namespace texsim::pipelines::fluid_lapped {
namespace {

using geom::Vec3;
using Uv = Eigen::Vector2d;

TEST(TriangleDistortion, MatchesHandValues) {
  const std::array<Uv, 3> rest{Uv(0, 0), Uv(1, 0), Uv(0, 1)};
  // A rigid motion (rotated and lifted into 3D): 1.
  EXPECT_NEAR(triangle_distortion(rest, {Vec3(1, 1, 1), Vec3(1, 1, 2), Vec3(1, 0, 1)}), 1.0, 1e-12);
  // Stretch by 2 along x: s1 = 2, s2 = 1.
  EXPECT_NEAR(triangle_distortion(rest, {Vec3(0, 0, 0), Vec3(2, 0, 0), Vec3(0, 1, 0)}), 2.0, 1e-12);
  // Shrink by 1/3 along y: 1 / s2 = 3.
  EXPECT_NEAR(triangle_distortion(rest, {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1.0 / 3, 0)}), 3.0,
              1e-12);
  // Shear [[1, 1], [0, 1]]: singular values (sqrt(5) +- 1) / 2, so delta = golden ratio.
  EXPECT_NEAR(triangle_distortion(rest, {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(1, 1, 0)}),
              (std::sqrt(5.0) + 1) / 2, 1e-12);
  // Collapsed: infinite.
  EXPECT_TRUE(std::isinf(triangle_distortion(rest, {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(2, 0, 0)})));
}

TEST(TriangleQuality, IsEquationOne) {
  EXPECT_DOUBLE_EQ(triangle_quality(1.0, 3.0), 1.0);
  EXPECT_DOUBLE_EQ(triangle_quality(2.0, 3.0), 0.5);
  EXPECT_DOUBLE_EQ(triangle_quality(3.0, 3.0), 0.0);
  EXPECT_DOUBLE_EQ(triangle_quality(7.0, 3.0), 0.0);
}

/// A 4 x 4 grid patch of side 1 (r = 0.5) around its centre, rest = current.
Patch grid_patch(double radius) {
  Patch patch;
  patch.id = 0;
  const int n = 4;
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i) {
      patch.positions.emplace_back(double(i) / n, double(j) / n, 0.0);
      patch.rest_uv.push_back(Uv(0.5, 0.5) +
                              (Uv(double(i) / n, double(j) / n) - Uv(0.5, 0.5)) * (0.5 / radius));
      patch.surface_triangle.push_back(0);
    }
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const int v = j * (n + 1) + i;
      patch.triangles.push_back({v, v + 1, v + n + 2});
      patch.triangles.push_back({v, v + n + 2, v + n + 1});
    }
  patch.weights.assign(patch.positions.size(), -1.0);
  return patch;
}

TEST(PatchWeights, BoundaryFarFromPIsZeroInteriorIsQuality) {
  const double r = 0.5;
  auto patch = grid_patch(r);
  update_weights(patch, r);
  for (std::size_t v = 0; v < patch.positions.size(); ++v) {
    const auto& p = patch.positions[v];
    const bool boundary = p.x() == 0 || p.x() == 1 || p.y() == 0 || p.y() == 1;
    EXPECT_DOUBLE_EQ(patch.weights[v], boundary ? 0.0 : 1.0) << v;
  }
  // Stretch x by 2 (delta 2, Q 0.5) everywhere: interior weights 0.5.
  for (auto& p : patch.positions)
    p.x() *= 2;
  update_weights(patch, r);
  EXPECT_DOUBLE_EQ(patch.weights[12], 0.5); // the centre vertex (2, 2)
  // Beyond delta_max every weight is 0.
  for (auto& p : patch.positions)
    p.x() *= 2;
  update_weights(patch, r);
  for (const double w : patch.weights)
    EXPECT_EQ(w, 0.0);
}

TEST(PatchWeights, CornersOfPsTriangleKeepBoundaryWeightOne) {
  // A single triangle holding p: every corner is a boundary vertex farther than r / 4.
  Patch patch;
  patch.positions = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0)};
  patch.rest_uv = {Uv(0.3, 0.3), Uv(0.8, 0.3), Uv(0.3, 0.8)};
  patch.triangles = {{0, 1, 2}};
  patch.surface_triangle = {0, 0, 0};
  update_weights(patch, 1.0);
  for (const double w : patch.weights)
    EXPECT_DOUBLE_EQ(w, 1.0);
}

FrameSurface flat_frame() {
  return FrameSurface(geom::plane(Vec3(2, 2, 0), 40));
}

TEST(PatchBuilder, FlatPatchIsAnIsometryCentredOnP) {
  const auto frame = flat_frame();
  const double r = 0.3;
  const geom::SurfacePoint p{Vec3(1.013, 0.977, 0),
                             frame.tree.closest_point(Vec3(1.013, 0.977, 0)).triangle};
  auto patch = build_patch(frame, p, r, 7, 0, 1, 7);
  update_weights(patch, r);
  ASSERT_GT(patch.triangles.size(), 20u);
  std::vector<std::int32_t> triangles(patch.triangles.size());
  // uv(p) = (0.5, 0.5) and uv distances are surface distances x 0.5 / r.
  for (std::size_t a = 0; a < patch.positions.size(); ++a) {
    EXPECT_LE((patch.positions[a] - p.position).norm(), r + 2.0 / 40 * std::sqrt(2.0));
    for (std::size_t b = a + 1; b < patch.positions.size(); b += 7)
      EXPECT_NEAR((patch.rest_uv[a] - patch.rest_uv[b]).norm(),
                  (patch.positions[a] - patch.positions[b]).norm() * 0.5 / r, 1e-9);
  }
  const auto& t = patch.triangles.front();
  const auto w = geom::barycentric_weights(patch.positions[std::size_t(t[0])],
                                           patch.positions[std::size_t(t[1])],
                                           patch.positions[std::size_t(t[2])], p.position);
  Uv centre = Uv::Zero();
  for (int c = 0; c < 3; ++c)
    centre += w[std::size_t(c)] * patch.rest_uv[std::size_t(t[std::size_t(c)])];
  EXPECT_NEAR((centre - Uv(0.5, 0.5)).norm(), 0.0, 1e-12);
  // delta_t = 1: every interior vertex has weight 1.
  EXPECT_GT(*std::max_element(patch.weights.begin(), patch.weights.end()), 1.0 - 1e-9);
  // The same bytes twice; another id turns the uv.
  const auto again = build_patch(frame, p, r, 7, 0, 1, 7);
  EXPECT_EQ(again.rest_uv, patch.rest_uv);
  const auto other = build_patch(frame, p, r, 8, 0, 1, 8);
  EXPECT_NE(other.rest_uv, patch.rest_uv);
}

TEST(PatchBuilder, ThinSlabKeepsTheFarSheetOut) {
  // Two parallel sheets 0.1 r apart with opposite normals (a thin film of fluid).
  const double r = 0.5;
  auto top = geom::plane(Vec3(2, 2, 0), 20);
  const auto bottom_count = std::int32_t(top.positions.size());
  auto slab = top;
  for (auto p : top.positions)
    slab.positions.push_back(p + Vec3(0, 0, -0.1 * r));
  for (auto t : top.triangles)
    slab.triangles.push_back({t[0] + bottom_count, t[2] + bottom_count, t[1] + bottom_count});
  const FrameSurface frame(slab);
  const Vec3 at(1.02, 0.98, 0);
  const auto patch = build_patch(frame, {at, frame.tree.closest_point(at).triangle}, r, 0, 0, 1, 0);
  for (const auto& p : patch.positions)
    EXPECT_EQ(p.z(), 0.0);
}

TEST(PatchBuilder, SpherePatchIsADisk) {
  const FrameSurface frame(geom::icosphere(4));
  for (std::int64_t id = 0; id < 5; ++id) {
    const auto p = geom::random_surface_points(frame.mesh, id, 1, 9).front();
    const auto patch = build_patch(frame, p, 0.4, id, 0, 9, std::uint64_t(id));
    geom::TriangleMesh mesh{patch.positions, patch.triangles};
    std::vector<std::int32_t> all(patch.triangles.size());
    std::iota(all.begin(), all.end(), 0);
    EXPECT_TRUE(geom::is_topological_disk(mesh, all)) << id;
    for (const auto& p_v : patch.positions)
      EXPECT_LE((p_v - p.position).norm(), 0.4 + 0.2);
  }
}

TEST(PoissonDisk, SpacingAndNoGaps) {
  const auto sphere = geom::icosphere(4);
  const double r = 0.2;
  const auto points = geom::poisson_disk_points(sphere, r, 5);
  for (std::size_t a = 0; a < points.size(); ++a)
    for (std::size_t b = a + 1; b < points.size(); ++b)
      ASSERT_GT((points[a].position - points[b].position).norm(), r) << a << " " << b;
  // Every surface point within 1.125 r of a centre (the fill's guarantee); most within r.
  std::size_t within_r = 0;
  const auto samples = geom::random_surface_points(sphere, 0, 4000, 77);
  for (const auto& s : samples) {
    double nearest = 1e9;
    for (const auto& p : points)
      nearest = std::min(nearest, (p.position - s.position).norm());
    EXPECT_LE(nearest, 1.125 * r);
    within_r += nearest <= r;
  }
  EXPECT_GT(double(within_r) / double(samples.size()), 0.99);
  // Disks of radius r around the points cover the surface (maximal), disks of radius r / 2 do
  // not overlap (spacing): area / (pi r^2) <= count <= 0.907 area / (pi r^2 / 4), with a few
  // percent for the curvature of a unit sphere.
  const double area = 4 * M_PI;
  EXPECT_GT(double(points.size()), 0.95 * area / (M_PI * r * r));
  EXPECT_LT(double(points.size()), 1.05 * 0.907 * area / (M_PI * r * r / 4));
  EXPECT_EQ(geom::poisson_disk_points(sphere, r, 5).size(), points.size());
}

} // namespace
} // namespace texsim::pipelines::fluid_lapped
