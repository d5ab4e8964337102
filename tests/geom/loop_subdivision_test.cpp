#include "geom/generators.hpp"
#include "geom/loop_subdivision.hpp"
#include "geom/mesh_measures.hpp"
#include "geom/mesh_topology.hpp"
#include "geom/mesh_validation.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

namespace texsim::geom {
namespace {

/// Largest angle (radians) between the normals of two triangles sharing an edge.
double max_dihedral_turn(const TriangleMesh& mesh) {
  const MeshTopology topo(mesh);
  const auto normals = triangle_normals(mesh);
  double worst = 0.0;
  for (std::int32_t e = 0; e < topo.num_edges(); ++e) {
    const auto around = topo.edge_triangles(e);
    const double cosine = std::clamp(normals[around[0]].dot(normals[around[1]]), -1.0, 1.0);
    worst = std::max(worst, std::acos(cosine));
  }
  return worst;
}

TEST(LoopSubdivision, EachLevelAddsOneVertexPerEdge) {
  auto mesh = icosphere(1);
  for (int level = 1; level <= 3; ++level) {
    const MeshTopology topo(mesh);
    const auto finer = loop_subdivide(mesh, 1);
    EXPECT_EQ(finer.num_vertices(), topo.num_vertices() + topo.num_edges());
    EXPECT_EQ(finer.num_triangles(), 4 * mesh.num_triangles());
    EXPECT_TRUE(validate(finer).clean());
    EXPECT_EQ(MeshTopology(finer).euler_characteristic(), 2);
    mesh = finer;
  }
  EXPECT_EQ(loop_subdivide(icosphere(1), 3).num_vertices(), mesh.num_vertices());
  EXPECT_EQ(loop_subdivide(icosphere(1), 0).positions, icosphere(1).positions);
}

TEST(LoopSubdivision, SmoothsTowardsTheLimitSurfaceAndKeepsArea) {
  const auto coarse = icosphere(1);
  const double area = total_area(coarse);
  double previous_turn = max_dihedral_turn(coarse);
  double previous_area = area, previous_change = 0.0;
  for (int levels = 1; levels <= 3; ++levels) {
    const auto fine = loop_subdivide(coarse, levels);
    const double turn = max_dihedral_turn(fine);
    // Approximating subdivision: the surface shrinks a little inside the control mesh, the area
    // converges to the limit surface's, and the kinks between neighbouring triangles shrink by
    // about half per level.
    EXPECT_LT(turn, 0.6 * previous_turn) << "levels " << levels;
    const double fine_area = total_area(fine);
    EXPECT_NEAR(fine_area, area, 0.15 * area) << "levels " << levels;
    const double change = std::abs(fine_area - previous_area);
    if (levels > 1) {
      EXPECT_LT(change, 0.5 * previous_change) << "levels " << levels;
    }
    previous_area = fine_area;
    previous_change = change;
    for (const auto& p : fine.positions) {
      ASSERT_LT(p.norm(), 1.0 + 1e-12);
      ASSERT_GT(p.norm(), 0.85);
    }
    previous_turn = turn;
  }
}

} // namespace
} // namespace texsim::geom
