// Walking points along a surface: straight lines on a flat mesh, unfolding across the edges of a
// cube (length preserved, expected end points), staying on the surface of a sphere, stopping at
// boundary and non-manifold edges.
#include "geom/generators.hpp"
#include "geom/mesh_topology.hpp"
#include "geom/random_surface_points.hpp"
#include "geom/surface_walker.hpp"

#include <gtest/gtest.h>

#include <Eigen/Dense>

#include <cmath>

namespace texsim::geom {
namespace {

// Barycentric coordinates of p in triangle t and its distance from the triangle's plane, by least
// squares on the corners (independent of the walker's own frames).
struct OnTriangle {
  Eigen::Vector3d barycentric;
  double plane_distance;
};
OnTriangle locate(const TriangleMesh& mesh, std::int32_t t, const Vec3& p) {
  const auto& tri = mesh.triangles[t];
  const Vec3 a = mesh.positions[tri[0]], b = mesh.positions[tri[1]], c = mesh.positions[tri[2]];
  Eigen::Matrix<double, 3, 2> edges;
  edges << b - a, c - a;
  const Eigen::Vector2d st = edges.colPivHouseholderQr().solve(p - a);
  const Vec3 normal = (b - a).cross(c - a).normalized();
  return {Eigen::Vector3d(1.0 - st[0] - st[1], st[0], st[1]), std::abs(normal.dot(p - a))};
}

void expect_on_triangle(const TriangleMesh& mesh, const SurfacePoint& p) {
  ASSERT_GE(p.triangle, 0);
  ASSERT_LT(p.triangle, mesh.num_triangles());
  const auto where = locate(mesh, p.triangle, p.position);
  EXPECT_LT(where.plane_distance, 1e-12) << p.position.transpose();
  EXPECT_GE(where.barycentric.minCoeff(), -1e-12) << p.position.transpose();
}

// The triangle of `mesh` holding p (first found), by barycentric coordinates.
std::int32_t find_triangle(const TriangleMesh& mesh, const Vec3& p) {
  for (std::int32_t t = 0; t < mesh.num_triangles(); ++t) {
    const auto where = locate(mesh, t, p);
    if (where.plane_distance < 1e-12 && where.barycentric.minCoeff() > -1e-12)
      return t;
  }
  return -1;
}

// [0, n]^2 in the plane z = 0, unit squares split along alternating diagonals.
TriangleMesh flat_grid(int n) {
  TriangleMesh mesh;
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i)
      mesh.positions.emplace_back(i, j, 0.0);
  const auto id = [n](int i, int j) { return j * (n + 1) + i; };
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      if ((i + j) % 2 == 0) {
        mesh.triangles.push_back({id(i, j), id(i + 1, j), id(i + 1, j + 1)});
        mesh.triangles.push_back({id(i, j), id(i + 1, j + 1), id(i, j + 1)});
      } else {
        mesh.triangles.push_back({id(i, j), id(i + 1, j), id(i, j + 1)});
        mesh.triangles.push_back({id(i + 1, j), id(i + 1, j + 1), id(i, j + 1)});
      }
    }
  return mesh;
}

TEST(SurfaceWalker, WalkOnAFlatMeshIsStraightLineMotion) {
  const auto mesh = flat_grid(10);
  const MeshTopology topology(mesh);
  const SurfaceWalker walker(mesh, topology);
  const CounterRng rng(5, 1);
  for (int k = 0; k < 200; ++k) {
    const Vec3 start(rng.uniform(2.0, 8.0, k, 0), rng.uniform(2.0, 8.0, k, 1), 0.0);
    // Up to 2 units in the plane (many edges crossed, never leaving [0, 10]^2); the out-of-plane
    // part is projected away.
    const Vec3 d(rng.uniform(-2.0, 2.0, k, 2), rng.uniform(-2.0, 2.0, k, 3),
                 rng.uniform(-1.0, 1.0, k, 4));
    const SurfacePoint p{start, find_triangle(mesh, start)};
    ASSERT_GE(p.triangle, 0);
    const auto moved = walker.move(p, d);
    const Vec3 expected(start.x() + d.x(), start.y() + d.y(), 0.0);
    EXPECT_LT((moved.position - expected).norm(), 1e-12) << "walk " << k;
    expect_on_triangle(mesh, moved);
  }
  // Through vertices and along edges: diagonal walks pass exactly through grid vertices.
  for (const auto& [start, d] :
       std::vector<std::pair<Vec3, Vec3>>{{Vec3(2.5, 2.5, 0), Vec3(3, 3, 0)},
                                          {Vec3(1.5, 2.0, 0), Vec3(4, 0, 0)},
                                          {Vec3(3.0, 3.0, 0), Vec3(-2, 2, 0)},
                                          {Vec3(2.25, 7.5, 0), Vec3(5, -5, 0)}}) {
    const auto moved = walker.move({start, find_triangle(mesh, start)}, d);
    EXPECT_LT((moved.position - (start + d)).norm(), 1e-12) << start.transpose();
    expect_on_triangle(mesh, moved);
  }
}

TEST(SurfaceWalker, CrossingCubeEdgesUnfoldsThePathAndKeepsItsLength) {
  // Faces at +-1; each face a 4 x 4 grid of cells.
  const auto mesh = box(Vec3(2, 2, 2), 4);
  const MeshTopology topology(mesh);
  const SurfaceWalker walker(mesh, topology);
  struct Case {
    Vec3 start, displacement, end, end_normal;
  };
  const std::vector<Case> cases{
      // Over the edge x = 1 of the top face: 0.8 on top, then 0.7 down the +x face.
      {Vec3(0.2, 0.3, 1), Vec3(1.5, 0, 0), Vec3(1, 0.3, 0.3), Vec3(1, 0, 0)},
      // Obliquely: the edge is reached after half the path, the rest turns downwards.
      {Vec3(0.5, -0.2, 1), Vec3(1.0, 0.6, 0), Vec3(1, 0.4, 0.5), Vec3(1, 0, 0)},
      // Two edges: 0.1 on top, 2 down the +x face, 0.4 back along the bottom.
      {Vec3(0.9, 0, 1), Vec3(2.5, 0, 0), Vec3(0.6, 0, -1), Vec3(0, 0, -1)},
      // Three edges around the cube along y: 1.3 on top, 2 down, 2 along the bottom, 0.2 up.
      {Vec3(0.3, -0.3, 1), Vec3(0, 5.5, 0), Vec3(0.3, -1, -0.8), Vec3(0, -1, 0)},
      // Projection: the normal component of the displacement is dropped on the top face.
      {Vec3(0.2, 0.3, 1), Vec3(1.5, 0, 7), Vec3(1, 0.3, 0.3), Vec3(1, 0, 0)},
  };
  for (const auto& c : cases) {
    const SurfacePoint p{c.start, find_triangle(mesh, c.start)};
    ASSERT_GE(p.triangle, 0);
    const auto moved = walker.move(p, c.displacement);
    EXPECT_LT((moved.position - c.end).norm(), 1e-12)
        << "from " << c.start.transpose() << " by " << c.displacement.transpose() << " got "
        << moved.position.transpose();
    expect_on_triangle(mesh, moved);
    // The end triangle lies on the expected face.
    const auto& tri = mesh.triangles[moved.triangle];
    for (const auto v : tri)
      EXPECT_NEAR(mesh.positions[v].dot(c.end_normal), 1.0, 1e-12);
  }
  // There and back again: (1.4, 0.2) on the top face ends at (1, -0.25, 0.25) on the +x face,
  // where the reversed direction (up and to -y) leads back to the start.
  const Vec3 origin(0.35, -0.45, 1);
  const auto there = walker.move({origin, find_triangle(mesh, origin)}, Vec3(1.4, 0.2, 0));
  EXPECT_LT((there.position - Vec3(1, -0.25, 0.25)).norm(), 1e-12);
  const auto back = walker.move(there, Vec3(0, -0.2, 1.4));
  EXPECT_LT((back.position - origin).norm(), 1e-12);
}

TEST(SurfaceWalker, PointsStayOnTheSurfaceOfASphere) {
  const auto mesh = icosphere(3);
  const MeshTopology topology(mesh);
  const SurfaceWalker walker(mesh, topology);
  const auto starts = random_surface_points(mesh, 0, 500, 9);
  const CounterRng rng(9, 2);
  for (std::size_t k = 0; k < starts.size(); ++k) {
    // Up to half a radius: a walk over many triangles.
    const Vec3 d = 0.5 * Vec3(rng.uniform(-1.0, 1.0, k, 0), rng.uniform(-1.0, 1.0, k, 1),
                              rng.uniform(-1.0, 1.0, k, 2));
    const auto moved = walker.move(starts[k], d);
    expect_on_triangle(mesh, moved);
    // The length walked is the projected displacement; the chord is shorter but not by much
    // on a sphere of radius 1 (chord >= 2 sin(L/2) for a geodesic, looser for a polyhedron).
    const auto& tri = mesh.triangles[starts[k].triangle];
    const Vec3 normal = (mesh.positions[tri[1]] - mesh.positions[tri[0]])
                            .cross(mesh.positions[tri[2]] - mesh.positions[tri[0]])
                            .normalized();
    const double walked = (d - normal * normal.dot(d)).norm();
    const double chord = (moved.position - starts[k].position).norm();
    EXPECT_LE(chord, walked + 1e-12);
    EXPECT_GE(chord, 0.9 * walked);
  }
  // A very long walk ends, on the surface.
  const auto far = walker.move(starts[0], Vec3(40, 25, -10));
  expect_on_triangle(mesh, far);
  // Zero displacement keeps the point where it is.
  const auto still = walker.move(starts[1], Vec3::Zero());
  EXPECT_EQ(still.triangle, starts[1].triangle);
  EXPECT_LT((still.position - starts[1].position).norm(), 1e-15);
}

TEST(SurfaceWalker, StopsOnBoundaryAndNonManifoldEdges) {
  const auto mesh = flat_grid(10);
  const MeshTopology topology(mesh);
  const SurfaceWalker walker(mesh, topology);
  // Out through x = 10 after a third of the path.
  const Vec3 start(9, 5, 0);
  const auto stopped = walker.move({start, find_triangle(mesh, start)}, Vec3(3, 1, 0));
  EXPECT_LT((stopped.position - Vec3(10, 5 + 1.0 / 3.0, 0)).norm(), 1e-12);
  expect_on_triangle(mesh, stopped);
  // Into a corner.
  const Vec3 near_corner(0.5, 0.25, 0);
  const auto cornered =
      walker.move({near_corner, find_triangle(mesh, near_corner)}, Vec3(-1, -0.5, 0));
  EXPECT_LT((cornered.position - Vec3(0, 0, 0)).norm(), 1e-12);

  // Three triangles sharing the edge (0,0,0)-(0,1,0): a fin.
  TriangleMesh fin;
  fin.positions = {Vec3(0, 0, 0), Vec3(0, 1, 0), Vec3(1, 0.5, 0), Vec3(-1, 0.5, 0),
                   Vec3(0, 0.5, 1)};
  fin.triangles = {{0, 2, 1}, {0, 1, 3}, {0, 1, 4}};
  const MeshTopology fin_topology(fin);
  const SurfaceWalker fin_walker(fin, fin_topology);
  EXPECT_EQ(fin_walker.neighbor(0, 1), -1); // the edge 0-1, opposite corner 1
  const auto at_fin = fin_walker.move({Vec3(0.5, 0.5, 0), 0}, Vec3(-2, 0.2, 0));
  EXPECT_EQ(at_fin.triangle, 0);
  EXPECT_LT((at_fin.position - Vec3(0, 0.55, 0)).norm(), 1e-12);

  // Two triangles sharing an edge at a right angle: the walk continues up the wall.
  TriangleMesh corner;
  corner.positions = {Vec3(0, 0, 0), Vec3(0, 1, 0), Vec3(1, 0.5, 0), Vec3(0, 0.5, 1)};
  corner.triangles = {{0, 2, 1}, {0, 1, 3}};
  const MeshTopology corner_topology(corner);
  const SurfaceWalker corner_walker(corner, corner_topology);
  EXPECT_EQ(corner_walker.neighbor(0, 1), 1);
  const auto climbed = corner_walker.move({Vec3(0.5, 0.5, 0), 0}, Vec3(-0.7, 0, 0));
  EXPECT_EQ(climbed.triangle, 1);
  EXPECT_LT((climbed.position - Vec3(0, 0.5, 0.2)).norm(), 1e-12);
}

} // namespace
} // namespace texsim::geom
