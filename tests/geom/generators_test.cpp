#include "geom/generators.hpp"
#include "geom/mesh_measures.hpp"
#include "geom/mesh_topology.hpp"
#include "geom/mesh_validation.hpp"

#include <Eigen/Geometry>
#include <gtest/gtest.h>

#include <cmath>

namespace texsim::geom {
namespace {

/// Volume enclosed by a closed mesh, positive when its triangles face outward.
double signed_volume(const TriangleMesh& mesh) {
  double volume = 0.0;
  for (const auto& tri : mesh.triangles) {
    volume += mesh.positions[tri[0]].dot(mesh.positions[tri[1]].cross(mesh.positions[tri[2]]));
  }
  return volume / 6.0;
}

TEST(Icosphere, CountsPerLevelAndVerticesOnSphere) {
  for (const int level : {0, 1, 2, 3, 7}) {
    const auto mesh = icosphere(level, 2.5);
    const auto factor = std::int32_t{1} << (2 * level);
    EXPECT_EQ(mesh.num_vertices(), 10 * factor + 2) << "level " << level;
    EXPECT_EQ(mesh.num_triangles(), 20 * factor) << "level " << level;
    for (const auto& p : mesh.positions) {
      ASSERT_NEAR(p.norm(), 2.5, 1e-12);
    }
  }
  EXPECT_EQ(icosphere(7).num_vertices(), 163842);
  const auto mesh = icosphere(3, 2.5);
  EXPECT_TRUE(validate(mesh).clean());
  const double exact = 4.0 / 3.0 * M_PI * std::pow(2.5, 3);
  EXPECT_GT(signed_volume(mesh), 0.97 * exact);
  EXPECT_LT(signed_volume(mesh), exact);
}

TEST(Torus, AreaConvergesToExactAtSecondOrder) {
  const double major = 3.0, minor = 1.0;
  const double exact = 4.0 * M_PI * M_PI * major * minor;
  double previous = 0.0;
  for (const int n : {16, 32, 64}) {
    const auto mesh = torus(major, minor, 2 * n, n);
    EXPECT_EQ(mesh.num_vertices(), 2 * n * n);
    const double error = std::abs(total_area(mesh) - exact);
    if (previous > 0.0) {
      EXPECT_NEAR(previous / error, 4.0, 0.3) << "n = " << n;
    }
    previous = error;
  }
  EXPECT_LT(previous / exact, 1e-3);
  const auto mesh = torus(major, minor, 32, 16);
  EXPECT_TRUE(validate(mesh).clean());
  EXPECT_NEAR(signed_volume(mesh), 2.0 * M_PI * M_PI * major * minor * minor, 0.05 * 59.2);
}

TEST(Box, WatertightWithSharpRightAngledEdges) {
  const Vec3 size(1.0, 2.0, 3.0);
  const int n = 4;
  const auto mesh = box(size, n);
  EXPECT_EQ(mesh.num_vertices(), 6 * n * n + 2);
  EXPECT_EQ(mesh.num_triangles(), 12 * n * n);
  const MeshTopology topo(mesh);
  EXPECT_EQ(topo.euler_characteristic(), 2);
  EXPECT_TRUE(topo.is_closed());
  EXPECT_TRUE(topo.is_manifold());
  EXPECT_TRUE(validate(mesh).clean());
  EXPECT_NEAR(total_area(mesh), 2.0 * (1 * 2 + 2 * 3 + 3 * 1), 1e-12);
  EXPECT_NEAR(signed_volume(mesh), 6.0, 1e-12);

  const auto normals = triangle_normals(mesh);
  int right_angles = 0;
  for (std::int32_t e = 0; e < topo.num_edges(); ++e) {
    const auto around = topo.edge_triangles(e);
    const double cosine = normals[around[0]].dot(normals[around[1]]);
    if (std::abs(cosine) < 1e-12) {
      ++right_angles;
    } else {
      ASSERT_NEAR(cosine, 1.0, 1e-12) << "edge " << e << " is neither flat nor a right angle";
    }
  }
  EXPECT_EQ(right_angles, 12 * n);
  // Every triangle faces away from the centre along a coordinate axis.
  for (std::int32_t t = 0; t < mesh.num_triangles(); ++t) {
    const Vec3 centroid =
        (mesh.positions[mesh.triangles[t][0]] + mesh.positions[mesh.triangles[t][1]] +
         mesh.positions[mesh.triangles[t][2]]) /
        3.0;
    ASSERT_GT(normals[t].dot(centroid), 0.0);
    ASSERT_NEAR(normals[t].cwiseAbs().maxCoeff(), 1.0, 1e-12);
  }
}

TEST(Noisy, DeterministicBoundedAlongNormals) {
  const auto base = icosphere(3);
  const double amplitude = 0.05;
  const auto a = noisy(base, amplitude, 42);
  const auto b = noisy(base, amplitude, 42);
  const auto c = noisy(base, amplitude, 43);
  EXPECT_EQ(a.positions, b.positions);
  EXPECT_EQ(a.triangles, base.triangles);
  const auto normals = vertex_normals(base);
  double sum_abs = 0.0;
  int differ = 0, outward = 0;
  for (std::int32_t v = 0; v < base.num_vertices(); ++v) {
    const Vec3 d = a.positions[v] - base.positions[v];
    ASSERT_LE(d.norm(), amplitude);
    ASSERT_LT(d.cross(normals[v]).norm(), 1e-15);
    sum_abs += d.norm();
    outward += d.dot(normals[v]) > 0.0 ? 1 : 0;
    differ += a.positions[v] != c.positions[v] ? 1 : 0;
  }
  EXPECT_EQ(differ, base.num_vertices());
  // U(-1, 1): mean |displacement| is amplitude / 2, about half the vertices move outward.
  EXPECT_NEAR(sum_abs / base.num_vertices(), amplitude / 2.0, 0.05 * amplitude);
  EXPECT_NEAR(static_cast<double>(outward) / base.num_vertices(), 0.5, 0.08);
}

} // namespace
} // namespace texsim::geom
