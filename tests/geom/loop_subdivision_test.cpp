#include "geom/cgal_surface_mesh.hpp"
#include "geom/generators.hpp"
#include "geom/loop_subdivision.hpp"
#include "geom/mesh_measures.hpp"
#include "geom/mesh_topology.hpp"
#include "geom/mesh_validation.hpp"

#include <CGAL/subdivision_method_3.h>
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

/// CGAL's Loop subdivision (Subdivision_method_3), an independent reference.
TriangleMesh cgal_loop(const TriangleMesh& mesh, int levels) {
  auto surface = cgal::to_surface_mesh(mesh, "cgal_loop");
  CGAL::Subdivision_method_3::Loop_subdivision(surface,
                                               CGAL::parameters::number_of_iterations(levels));
  surface.collect_garbage();
  return cgal::to_triangle_mesh(surface, "cgal_loop");
}

/// Largest distance from a vertex of `ours` to the nearest vertex of `reference`, over the
/// mesh's size; and whether both have as many vertices and triangles.
double farthest_vertex(const TriangleMesh& ours, const TriangleMesh& reference) {
  EXPECT_EQ(ours.num_vertices(), reference.num_vertices());
  EXPECT_EQ(ours.num_triangles(), reference.num_triangles());
  double farthest = 0, size = 0;
  for (const auto& p : ours.positions) {
    double nearest = INFINITY;
    for (const auto& q : reference.positions)
      nearest = std::min(nearest, (p - q).norm());
    farthest = std::max(farthest, nearest);
    size = std::max(size, p.norm());
  }
  return farthest / size;
}

// The masks are CGAL's: the same surface, vertex for vertex, on a closed noisy sphere (valences 5
// and 6, irregular positions) and on an open noisy square (the boundary masks).
TEST(LoopSubdivision, EqualsCgalsLoopSubdivision) {
  const auto sphere = noisy(icosphere(1), 0.05, 7);
  EXPECT_LT(farthest_vertex(loop_subdivide(sphere, 2), cgal_loop(sphere, 2)), 1e-13);
  const auto square = noisy(plane(Vec3(1, 1, 0), 3), 0.05, 8);
  EXPECT_LT(farthest_vertex(loop_subdivide(square, 2), cgal_loop(square, 2)), 1e-13);
  // The comparison sees one vertex moved by 1e-6.
  auto skewed = loop_subdivide(square, 2);
  skewed.positions.back() += Vec3(1e-6, 0, 0);
  EXPECT_GT(farthest_vertex(skewed, cgal_loop(square, 2)), 1e-8);
}

} // namespace
} // namespace texsim::geom
