#include "geom/curvature_tensor.hpp"
#include "geom/generators.hpp"
#include "geom/mesh_measures.hpp"
#include "geom/mesh_topology.hpp"

#include <Eigen/Geometry>
#include <gtest/gtest.h>
#include <omp.h>

#include <algorithm>
#include <cmath>
#include <functional>

namespace texsim::geom {
namespace {

std::vector<PrincipalCurvature> curvatures_of(const TriangleMesh& mesh) {
  return principal_curvatures(mesh, MeshTopology(mesh));
}

/// A (rows + 1) x (cols + 1) vertex grid, point(i, j) giving the positions, quads split along
/// alternating diagonals; open (the grid's outline is a boundary).
TriangleMesh grid_surface(int rows, int cols, const std::function<Vec3(int, int)>& point) {
  TriangleMesh mesh;
  for (int i = 0; i <= rows; ++i) {
    for (int j = 0; j <= cols; ++j) {
      mesh.positions.push_back(point(i, j));
    }
  }
  const auto id = [&](int i, int j) { return i * (cols + 1) + j; };
  for (int i = 0; i < rows; ++i) {
    for (int j = 0; j < cols; ++j) {
      if ((i + j) % 2 == 0) {
        mesh.triangles.push_back({id(i, j), id(i, j + 1), id(i + 1, j + 1)});
        mesh.triangles.push_back({id(i, j), id(i + 1, j + 1), id(i + 1, j)});
      } else {
        mesh.triangles.push_back({id(i, j), id(i, j + 1), id(i + 1, j)});
        mesh.triangles.push_back({id(i, j + 1), id(i + 1, j + 1), id(i + 1, j)});
      }
    }
  }
  return mesh;
}

void expect_right_handed_frames(const std::vector<PrincipalCurvature>& curvatures) {
  for (std::size_t v = 0; v < curvatures.size(); ++v) {
    const auto& c = curvatures[v];
    ASSERT_NEAR(c.normal.norm(), 1.0, 1e-12) << "vertex " << v;
    ASSERT_NEAR(c.e1.norm(), 1.0, 1e-12) << "vertex " << v;
    ASSERT_NEAR(c.e1.dot(c.normal), 0.0, 1e-12) << "vertex " << v;
    ASSERT_LT((c.e1.cross(c.e2) - c.normal).norm(), 1e-12) << "vertex " << v;
    ASSERT_GE(c.k1, c.k2) << "vertex " << v;
  }
}

TEST(CurvatureTensor, SphereIsUmbilicWithCurvatureOneOverRadius) {
  // Max's normals are exactly radial for vertices on a sphere, so every normal difference is the
  // edge vector over r and the fitted tensor is I / r: the estimate is exact at every level.
  const double radius = 2.5;
  for (const int level : {2, 4, 5}) {
    const auto mesh = icosphere(level, radius);
    const auto curvatures = curvatures_of(mesh);
    expect_right_handed_frames(curvatures);
    for (std::int32_t v = 0; v < mesh.num_vertices(); ++v) {
      ASSERT_NEAR(curvatures[v].k1, 1.0 / radius, 1e-10) << "level " << level << " vertex " << v;
      ASSERT_NEAR(curvatures[v].k2, 1.0 / radius, 1e-10) << "level " << level << " vertex " << v;
      ASSERT_GT(curvatures[v].normal.dot(mesh.positions[v].normalized()), 1.0 - 1e-12);
    }
  }
}

TEST(CurvatureTensor, InwardFacingSphereHasNegativeCurvature) {
  auto mesh = icosphere(3, 2.0);
  for (auto& tri : mesh.triangles) {
    std::swap(tri[1], tri[2]);
  }
  for (const auto& c : curvatures_of(mesh)) {
    ASSERT_NEAR(c.k1, -0.5, 1e-10);
    ASSERT_NEAR(c.k2, -0.5, 1e-10);
  }
}

/// Largest errors of k1, k2 and principal directions over all vertices of a torus grid, against
/// the analytic k_tube = 1/r (direction along the tube circle) and
/// k_axis = cos v / (R + r cos v) (direction around the z axis).
struct TorusErrors {
  double k1 = 0.0;
  double k2 = 0.0;
  double direction = 0.0; // 1 - min |e . analytic|
};

TorusErrors torus_errors(double major, double minor, int n_major, int n_minor) {
  const auto mesh = torus(major, minor, n_major, n_minor);
  const auto curvatures = curvatures_of(mesh);
  expect_right_handed_frames(curvatures);
  TorusErrors errors;
  for (int i = 0; i < n_major; ++i) {
    const double u = 2.0 * M_PI * i / n_major;
    for (int j = 0; j < n_minor; ++j) {
      const double v = 2.0 * M_PI * j / n_minor;
      const auto& c = curvatures[static_cast<std::size_t>(i) * n_minor + j];
      const Vec3 tube(-std::sin(v) * std::cos(u), -std::sin(v) * std::sin(u), std::cos(v));
      const Vec3 around(-std::sin(u), std::cos(u), 0.0);
      errors.k1 = std::max(errors.k1, std::abs(c.k1 - 1.0 / minor));
      errors.k2 = std::max(errors.k2, std::abs(c.k2 - std::cos(v) / (major + minor * std::cos(v))));
      errors.direction = std::max(errors.direction, 1.0 - std::abs(c.e1.dot(tube)));
      errors.direction = std::max(errors.direction, 1.0 - std::abs(c.e2.dot(around)));
    }
  }
  return errors;
}

TEST(CurvatureTensor, TorusCurvaturesAndDirectionsConvergeToAnalytic) {
  const double major = 1.0;
  const double minor = 0.4;
  const TorusErrors coarse = torus_errors(major, minor, 64, 32);
  const TorusErrors fine = torus_errors(major, minor, 128, 64);
  // Within half a percent of the tube curvature 1/r = 2.5 on the fine grid, everywhere.
  EXPECT_LT(fine.k1, 0.005 / minor);
  EXPECT_LT(fine.k2, 0.005 / minor);
  EXPECT_LT(fine.direction, 1e-5);
  // Refinement by 2 shrinks the curvature errors (second order on this regular grid).
  EXPECT_GT(coarse.k1 / fine.k1, 3.0);
  EXPECT_GT(coarse.k2 / fine.k2, 3.0);
}

TEST(CurvatureTensor, TorusEquatorSigns) {
  const double major = 1.0;
  const double minor = 0.4;
  const int n_major = 128;
  const int n_minor = 64;
  const auto curvatures = curvatures_of(torus(major, minor, n_major, n_minor));
  for (int i = 0; i < n_major; ++i) {
    const auto& outer = curvatures[static_cast<std::size_t>(i) * n_minor];               // v = 0
    const auto& inner = curvatures[static_cast<std::size_t>(i) * n_minor + n_minor / 2]; // v = pi
    EXPECT_NEAR(outer.k1, 1.0 / minor, 0.01 / minor) << "u index " << i;
    EXPECT_NEAR(outer.k2, 1.0 / (major + minor), 0.01 / minor) << "u index " << i;
    EXPECT_NEAR(inner.k1, 1.0 / minor, 0.01 / minor) << "u index " << i;
    EXPECT_NEAR(inner.k2, -1.0 / (major - minor), 0.01 / minor) << "u index " << i;
    EXPECT_GT(std::abs(outer.e1.z()), 0.999) << "tube direction at the outer equator is +-z";
    EXPECT_GT(std::abs(inner.e1.z()), 0.999) << "tube direction at the inner equator is +-z";
  }
}

TEST(CurvatureTensor, FlatGridHasZeroCurvatureIncludingBoundary) {
  const auto mesh = grid_surface(10, 14, [](int i, int j) {
    return Vec3(0.3 * j + 0.05 * i, 0.2 * i, 0.0); // sheared grid
  });
  const auto curvatures = curvatures_of(mesh);
  expect_right_handed_frames(curvatures);
  for (const auto& c : curvatures) {
    EXPECT_NEAR(c.k1, 0.0, 1e-12);
    EXPECT_NEAR(c.k2, 0.0, 1e-12);
    EXPECT_GT(c.normal.z(), 1.0 - 1e-12);
  }
}

TEST(CurvatureTensor, OpenCylinderIncludingBoundaryRows) {
  // A half cylinder of radius 0.5 around the z axis, open on all four sides.
  const double radius = 0.5;
  const int rows = 20;
  const int cols = 40;
  const auto mesh = grid_surface(rows, cols, [&](int i, int j) {
    const double theta = M_PI * j / cols;
    return Vec3(radius * std::cos(theta), radius * std::sin(theta), 0.04 * i);
  });
  const MeshTopology topology(mesh);
  ASSERT_FALSE(topology.boundary_vertices().empty());
  const auto curvatures = principal_curvatures(mesh, topology);
  expect_right_handed_frames(curvatures);
  for (std::int32_t v = 0; v < mesh.num_vertices(); ++v) {
    const auto& c = curvatures[v];
    const Vec3 radial = Vec3(mesh.positions[v].x(), mesh.positions[v].y(), 0.0).normalized();
    const Vec3 around = Vec3::UnitZ().cross(radial);
    EXPECT_NEAR(c.k1, 1.0 / radius, 0.03 / radius) << "vertex " << v;
    EXPECT_NEAR(c.k2, 0.0, 0.03 / radius) << "vertex " << v;
    EXPECT_GT(std::abs(c.e1.dot(around)), 0.99) << "vertex " << v;
    EXPECT_GT(std::abs(c.e2.z()), 0.99) << "vertex " << v;
    EXPECT_GT(c.normal.dot(radial), 0.99) << "vertex " << v;
  }
}

TEST(CurvatureTensor, NoisySphereAveragesNearOneOverRadius) {
  const double radius = 1.5;
  const auto clean = icosphere(4, radius);
  const auto mesh = noisy(clean, 0.05 * mean_edge_length(clean), 7);
  const auto curvatures = curvatures_of(mesh);
  expect_right_handed_frames(curvatures);
  const auto areas = triangle_areas(mesh);
  std::vector<double> vertex_area(curvatures.size(), 0.0);
  for (std::size_t t = 0; t < areas.size(); ++t) {
    for (const auto v : mesh.triangles[t]) {
      vertex_area[v] += areas[t] / 3.0;
    }
  }
  double weighted_mean = 0.0;
  double total = 0.0;
  double spread = 0.0;
  for (std::size_t v = 0; v < curvatures.size(); ++v) {
    const double mean_curvature = 0.5 * (curvatures[v].k1 + curvatures[v].k2);
    weighted_mean += vertex_area[v] * mean_curvature;
    total += vertex_area[v];
    spread = std::max(spread, std::abs(mean_curvature - 1.0 / radius));
  }
  weighted_mean /= total;
  EXPECT_NEAR(weighted_mean, 1.0 / radius, 0.03 / radius);
  EXPECT_GT(spread, 0.05 / radius) << "the noise must be visible per vertex for this test to bite";
}

TEST(CurvatureTensor, ResultDoesNotDependOnThreadCount) {
  const auto mesh = noisy(torus(1.0, 0.3, 40, 20), 0.01, 3);
  const MeshTopology topology(mesh);
  const int threads = omp_get_max_threads();
  omp_set_num_threads(1);
  const auto serial = principal_curvatures(mesh, topology);
  omp_set_num_threads(std::max(threads, 3));
  const auto parallel = principal_curvatures(mesh, topology);
  omp_set_num_threads(threads);
  for (std::size_t v = 0; v < serial.size(); ++v) {
    ASSERT_EQ(serial[v].k1, parallel[v].k1);
    ASSERT_EQ(serial[v].k2, parallel[v].k2);
    ASSERT_EQ(serial[v].e1, parallel[v].e1);
  }
}

TEST(CurvatureTensor, VertexWithoutTrianglesGetsZeroCurvature) {
  auto mesh = icosphere(1);
  mesh.positions.emplace_back(5.0, 5.0, 5.0);
  const auto curvatures = curvatures_of(mesh);
  const auto& lonely = curvatures.back();
  EXPECT_EQ(lonely.k1, 0.0);
  EXPECT_EQ(lonely.k2, 0.0);
  EXPECT_NEAR(lonely.normal.norm(), 1.0, 1e-12);
  EXPECT_NEAR(lonely.e1.dot(lonely.normal), 0.0, 1e-12);
}

} // namespace
} // namespace texsim::geom
