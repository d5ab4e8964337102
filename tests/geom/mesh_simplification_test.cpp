#include "geom/mesh_simplification.hpp"

#include "geom/generators.hpp"
#include "geom/mesh_measures.hpp"
#include "geom/mesh_topology.hpp"
#include "geom/mesh_validation.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

namespace texsim::geom {
namespace {

TEST(MeshSimplification, SphereKeepsTopologyShapeAndArea) {
  const auto fine = icosphere(5);
  ASSERT_EQ(fine.num_triangles(), 20480);
  const auto coarse = simplify(fine, 2000);
  EXPECT_LE(coarse.num_triangles(), 2000);
  EXPECT_GE(coarse.num_triangles(), 1990);
  EXPECT_TRUE(validate(coarse).clean());
  const MeshTopology topo(coarse);
  EXPECT_TRUE(topo.is_closed());
  EXPECT_TRUE(topo.is_manifold());
  EXPECT_EQ(topo.euler_characteristic(), 2);
  EXPECT_TRUE(topo.isolated_vertices().empty());
  double worst = 0.0;
  for (const auto& p : coarse.positions) {
    worst = std::max(worst, std::abs(p.norm() - 1.0));
  }
  EXPECT_LT(worst, 0.01);
  EXPECT_NEAR(total_area(coarse), total_area(fine), 0.02 * total_area(fine));
  // Every triangle still faces outwards: collapses kept the orientation.
  const auto normals = triangle_normals(coarse);
  for (std::int32_t t = 0; t < coarse.num_triangles(); ++t) {
    const auto& tri = coarse.triangles[t];
    const Vec3 centroid =
        (coarse.positions[tri[0]] + coarse.positions[tri[1]] + coarse.positions[tri[2]]) / 3.0;
    EXPECT_GT(normals[t].dot(centroid), 0.9 * centroid.norm()) << "triangle " << t;
  }
}

TEST(MeshSimplification, MeshAtOrBelowTargetIsReturnedUnchanged) {
  const auto mesh = icosphere(2);
  const auto same = simplify(mesh, mesh.triangles.size());
  EXPECT_EQ(same.positions, mesh.positions);
  EXPECT_EQ(same.triangles, mesh.triangles);
}

} // namespace
} // namespace texsim::geom
