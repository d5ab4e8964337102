#include "geom/generators.hpp"
#include "geom/mesh_measures.hpp"
#include "geom/mesh_reader.hpp"
#include "geom/mesh_remesh.hpp"
#include "geom/mesh_source.hpp"
#include "geom/mesh_topology.hpp"
#include "geom/mesh_validation.hpp"
#include "geom/triangle_quality.hpp"
#include "support/test_data.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <set>

namespace texsim::geom {
namespace {

TEST(TriangleQuality, EquilateralIsOneAndSliversGrow) {
  const Vec3 a(0, 0, 0), b(1, 0, 0), c(0.5, std::sqrt(3.0) / 2, 0);
  EXPECT_NEAR(aspect_ratio(a, b, c), 1.0, 1e-12);
  EXPECT_GT(aspect_ratio(a, b, Vec3(0.5, 0.01, 0)), 25.0);
  EXPECT_TRUE(std::isinf(aspect_ratio(a, b, Vec3(2, 0, 0))));

  TriangleMesh mesh;
  mesh.positions = {a, b, c, Vec3(0.5, -0.01, 0)};
  mesh.triangles = {{0, 1, 2}, {1, 0, 3}};
  const auto quality = triangle_quality(mesh);
  EXPECT_NEAR(quality.min_angle_deg, std::atan(0.02) * 180 / M_PI, 1e-9);
  EXPECT_EQ(quality.aspect_histogram[0], 1u); // [1, 1.5)
  EXPECT_EQ(quality.aspect_histogram[5], 1u); // [10, 100)
  EXPECT_EQ(quality.metrics()["aspect_ratio_histogram"]["[10,100)"], 1);
}

TEST(MeshRemesh, SphereReachesTheTargetEdgeLengthOnTheSurface) {
  const auto sphere = icosphere(2, 1.0); // edges about 0.3
  const auto remeshed = remesh_isotropic(sphere, {0.1, 3});
  EXPECT_NEAR(mean_edge_length(remeshed), 0.1, 0.015);
  EXPECT_TRUE(validate(remeshed).clean());
  EXPECT_EQ(MeshTopology(remeshed).euler_characteristic(), 2);
  // Vertices are projected onto the input polyhedron, which lies within 2% inside the sphere.
  for (const auto& p : remeshed.positions)
    EXPECT_NEAR(p.norm(), 1.0, 0.02);
  EXPECT_GT(triangle_quality(remeshed).min_angle_deg, 20.0);
}

TEST(MeshRemesh, BoundaryKeepsItsShape) {
  const auto box_mesh = box(Vec3(1, 1, 1), 4); // [-0.5, 0.5]^3
  TriangleMesh open = box_mesh;                // without the top face's triangles: open at z = 0.5
  open.triangles.clear();
  for (const auto& tri : box_mesh.triangles) {
    const bool top = box_mesh.positions[tri[0]].z() > 0.499 &&
                     box_mesh.positions[tri[1]].z() > 0.499 &&
                     box_mesh.positions[tri[2]].z() > 0.499;
    if (!top)
      open.triangles.push_back(tri);
  }
  MeshRepairOptions options;
  repair(open, options, "open_box");
  const auto remeshed = remesh_isotropic(open, {0.1, 3});
  const MeshTopology topology(remeshed);
  ASSERT_GT(topology.boundary_edges().size(), 0u);
  for (const auto e : topology.boundary_edges())
    for (const auto v : topology.edges()[e]) {
      const auto& p = remeshed.positions[v];
      EXPECT_NEAR(p.z(), 0.5, 1e-12);
      EXPECT_TRUE(std::abs(std::abs(p.x()) - 0.5) < 1e-12 ||
                  std::abs(std::abs(p.y()) - 0.5) < 1e-12)
          << p.transpose();
    }
  // The box's creases are not protected: remeshing rounds them off a little.
  EXPECT_NEAR(total_area(remeshed), total_area(open), 0.05 * total_area(open));
}

TEST(MeshRemeshOnRealData, MarchingCubesSliversBecomeWellShaped) {
  const std::string name = "scans/skull_ct_mc.ply";
  const auto path = test::real_data(name);
  if (path.empty())
    GTEST_SKIP() << test::missing_data_message(name);
  const auto mesh = read_mesh(path, MeshSource::fix_repair_options());
  const auto before = triangle_quality(mesh);
  const auto remeshed = remesh_isotropic(mesh, {mean_edge_length(mesh), 3});
  const auto after = triangle_quality(remeshed);
  EXPECT_LT(before.min_angle_deg, 5.0);
  EXPECT_GT(after.mean_min_angle_deg, before.mean_min_angle_deg + 5.0);
  const std::size_t slivers_before =
      before.aspect_histogram[4] + before.aspect_histogram[5] + before.aspect_histogram[6];
  const std::size_t slivers_after =
      after.aspect_histogram[4] + after.aspect_histogram[5] + after.aspect_histogram[6];
  EXPECT_LT(slivers_after * 10, slivers_before) << before.summary() << "\n" << after.summary();
  EXPECT_TRUE(validate(remeshed).clean());
}

} // namespace
} // namespace texsim::geom
