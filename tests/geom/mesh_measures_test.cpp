#include "geom/generators.hpp"
#include "geom/mesh_measures.hpp"

#include <Eigen/Geometry>
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <utility>

namespace texsim::geom {
namespace {

TEST(MeshMeasures, RightTriangleAreaNormalAndEdges) {
  TriangleMesh mesh;
  mesh.positions = {{0, 0, 0}, {3, 0, 0}, {0, 4, 0}};
  mesh.triangles = {{0, 1, 2}};
  EXPECT_DOUBLE_EQ(total_area(mesh), 6.0);
  EXPECT_TRUE(triangle_normals(mesh)[0].isApprox(Vec3(0, 0, 1)));
  EXPECT_DOUBLE_EQ(mean_edge_length(mesh), 4.0); // (3 + 4 + 5) / 3
  for (const auto& n : vertex_normals(mesh)) {
    EXPECT_TRUE(n.isApprox(Vec3(0, 0, 1)));
  }
}

TEST(MeshMeasures, VertexNormalsOfSpherePointOutward) {
  const auto mesh = icosphere(3, 2.0);
  const auto normals = vertex_normals(mesh);
  for (std::int32_t v = 0; v < mesh.num_vertices(); ++v) {
    // By symmetry of the icosphere the area-weighted normal is close to the radial direction.
    EXPECT_GT(normals[v].dot(mesh.positions[v].normalized()), 0.999) << "vertex " << v;
    EXPECT_NEAR(normals[v].norm(), 1.0, 1e-12);
  }
}

TEST(MeshMeasures, RunNormalsAreTheWholeMeshsBits) {
  const auto mesh = noisy(icosphere(3), 0.05, 2);
  const auto whole = vertex_normals(mesh);
  for (const auto& [first, count] :
       {std::pair<std::int64_t, std::int64_t>{0, 642}, {100, 1}, {317, 200}, {641, 1}, {5, 0}}) {
    const auto run = vertex_normals(mesh, first, count);
    ASSERT_EQ(run.size(), std::size_t(count));
    for (std::int64_t i = 0; i < count; ++i)
      EXPECT_EQ(std::memcmp(&run[std::size_t(i)], &whole[std::size_t(first + i)], sizeof(Vec3)), 0)
          << "vertex " << first + i;
  }
}

TEST(MeshMeasures, IcosphereAreaConvergesToSphereAtSecondOrder) {
  double previous_error = 0.0;
  for (int level = 1; level <= 5; ++level) {
    const double error = 4.0 * M_PI - total_area(icosphere(level));
    EXPECT_GT(error, 0.0); // inscribed polyhedron
    if (level > 1) {
      const double ratio = previous_error / error;
      EXPECT_GT(ratio, 3.5) << "level " << level;
      EXPECT_LT(ratio, 4.5) << "level " << level;
    }
    previous_error = error;
  }
  EXPECT_LT(previous_error / (4.0 * M_PI), 1e-3);
}

TEST(MeshMeasures, BarycentricWeightsRecoverTheProjectedPoint) {
  const Vec3 a(0.3, -1.0, 2.0), b(2.0, 0.5, 1.0), c(-0.5, 1.5, 0.0);
  const Vec3 normal = (b - a).cross(c - a).normalized();
  const std::array<double, 3> weights = {0.2, -0.3, 1.1}; // outside the triangle: not clamped
  const Vec3 in_plane = weights[0] * a + weights[1] * b + weights[2] * c;
  const auto w = barycentric_weights(a, b, c, in_plane + 0.7 * normal);
  for (int k = 0; k < 3; ++k)
    EXPECT_NEAR(w[k], weights[k], 1e-14);
  const auto degenerate = barycentric_weights(a, a, a, b);
  EXPECT_EQ(degenerate[0], 1.0);
  EXPECT_EQ(degenerate[1], 0.0);
}

} // namespace
} // namespace texsim::geom
