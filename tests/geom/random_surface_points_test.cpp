// Area-weighted random surface points: every point lies on its triangle, faces and sub-triangles
// receive points in proportion to their area (chi-square bounds), and a point depends only on
// (seed, id), not on how the ids are split into calls.
#include "core/error.hpp"
#include "geom/generators.hpp"
#include "geom/mesh_measures.hpp"
#include "geom/random_surface_points.hpp"

#include <gtest/gtest.h>

#include <Eigen/Dense>

#include <array>
#include <cmath>
#include <cstring>
#include <vector>

namespace texsim::geom {
namespace {

// Barycentric coordinates of p in triangle t and the distance of p from the triangle's plane,
// by least squares on the corners (independent of the code under test).
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

// Pearson's chi-square statistic of observed counts against expected probabilities.
double chi_square(const std::vector<double>& counts, const std::vector<double>& probabilities) {
  double total = 0.0;
  for (double c : counts)
    total += c;
  double chi2 = 0.0;
  for (std::size_t k = 0; k < counts.size(); ++k) {
    const double expected = total * probabilities[k];
    chi2 += (counts[k] - expected) * (counts[k] - expected) / expected;
  }
  return chi2;
}

TEST(RandomSurfacePoints, EveryPointLiesOnItsTriangle) {
  for (const auto& mesh : {icosphere(3, 2.0), torus(3.0, 1.0, 40, 16), box(Vec3(1, 2, 3), 3)}) {
    const auto points = random_surface_points(mesh, 0, 5000, 7);
    ASSERT_EQ(points.size(), 5000u);
    for (const auto& p : points) {
      ASSERT_GE(p.triangle, 0);
      ASSERT_LT(p.triangle, mesh.num_triangles());
      const auto where = locate(mesh, p.triangle, p.position);
      EXPECT_LT(where.plane_distance, 1e-12);
      EXPECT_GE(where.barycentric.minCoeff(), -1e-12);
    }
  }
}

TEST(RandomSurfacePoints, FacesOfABoxReceivePointsInProportionToArea) {
  // Every face has the same number of triangles, but the areas are 6 : 3 : 2 (yz : xz : xy), so
  // picking triangles uniformly instead of by area fails by far.
  const auto mesh = box(Vec3(1, 2, 3), 4);
  const std::int64_t n = 60000;
  const auto points = random_surface_points(mesh, 0, n, 11);
  std::vector<double> counts(6, 0.0);
  const Vec3 half(0.5, 1.0, 1.5);
  for (const auto& p : points) {
    int face = -1;
    for (int axis = 0; axis < 3; ++axis)
      for (int side = 0; side < 2; ++side)
        if (std::abs(p.position[axis] - (side == 0 ? -half[axis] : half[axis])) < 1e-12)
          face = 2 * axis + side;
    ASSERT_GE(face, 0) << "point off the box: " << p.position.transpose();
    counts[face] += 1.0;
  }
  const std::vector<double> expected{6.0 / 22, 6.0 / 22, 3.0 / 22, 3.0 / 22, 2.0 / 22, 2.0 / 22};
  // 5 degrees of freedom: P(chi2 > 20.5) = 0.001.
  EXPECT_LT(chi_square(counts, expected), 20.5);

  // Each half of the box (x < 0, x > 0; z < 0, z > 0) gets half the points.
  double x_negative = 0, z_negative = 0;
  for (const auto& p : points) {
    x_negative += p.position.x() < 0.0;
    z_negative += p.position.z() < 0.0;
  }
  EXPECT_LT(chi_square({x_negative, double(n) - x_negative}, {0.5, 0.5}), 10.8);
  EXPECT_LT(chi_square({z_negative, double(n) - z_negative}, {0.5, 0.5}), 10.8);
}

TEST(RandomSurfacePoints, PointsAreUniformInsideATriangle) {
  // The four sub-triangles cut by the edge midpoints have equal areas. Taking the barycentric
  // coordinates without the square-root warping crowds points into the corner-0 triangle.
  TriangleMesh mesh;
  mesh.positions = {Vec3(0, 0, 0), Vec3(4, 0, 0), Vec3(1, 3, 0)};
  mesh.triangles = {{0, 1, 2}};
  const auto points = random_surface_points(mesh, 0, 40000, 3);
  std::vector<double> counts(4, 0.0);
  for (const auto& p : points) {
    const auto where = locate(mesh, 0, p.position);
    int region = 3;
    for (int corner = 0; corner < 3; ++corner)
      if (where.barycentric[corner] > 0.5)
        region = corner;
    counts[region] += 1.0;
  }
  EXPECT_LT(chi_square(counts, {0.25, 0.25, 0.25, 0.25}), 16.3); // 3 dof, p = 0.001
}

TEST(RandomSurfacePoints, TrianglesOfAFineMeshReceivePointsInProportionToArea) {
  // A torus has triangles of different areas (larger outside); bin them by area into 5 groups.
  const auto mesh = torus(2.0, 1.0, 24, 12);
  const auto areas = triangle_areas(mesh);
  const double total = total_area(mesh);
  const auto points = random_surface_points(mesh, 0, 50000, 5);
  std::vector<double> counts(mesh.triangles.size(), 0.0);
  for (const auto& p : points)
    counts[p.triangle] += 1.0;
  std::vector<double> probabilities(areas.size());
  for (std::size_t t = 0; t < areas.size(); ++t)
    probabilities[t] = areas[t] / total;
  // 575 degrees of freedom: mean 575, std 34; 575 + 5 * 34 is far in the tail.
  EXPECT_LT(chi_square(counts, probabilities), 745.0);
}

TEST(RandomSurfacePoints, SameIdGivesTheSamePointWhateverTheSplit) {
  const auto mesh = icosphere(2);
  const auto whole = random_surface_points(mesh, 0, 1000, 42);
  std::vector<SurfacePoint> pieces;
  for (const auto& [first, count] : std::vector<std::pair<std::int64_t, std::int64_t>>{
           {0, 1}, {1, 299}, {300, 0}, {300, 517}, {817, 183}}) {
    const auto piece = random_surface_points(mesh, first, count, 42);
    pieces.insert(pieces.end(), piece.begin(), piece.end());
  }
  ASSERT_EQ(pieces.size(), whole.size());
  for (std::size_t i = 0; i < whole.size(); ++i) {
    EXPECT_EQ(pieces[i].triangle, whole[i].triangle);
    EXPECT_EQ(std::memcmp(pieces[i].position.data(), whole[i].position.data(), 3 * sizeof(double)),
              0)
        << "point " << i;
  }
  // The sampler alone gives the same point for the same id.
  const AreaSampler sampler(mesh);
  const CounterRng rng(42, kRandomSurfacePointStream);
  EXPECT_EQ(sampler.sample(rng, 517).position, whole[517].position);
  // Another seed gives other points.
  const auto other = random_surface_points(mesh, 0, 1000, 43);
  int same = 0;
  for (std::size_t i = 0; i < whole.size(); ++i)
    same += other[i].position == whole[i].position;
  EXPECT_EQ(same, 0);
}

TEST(AreaSampler, NeverPicksZeroAreaTrianglesAndRejectsMeshesWithoutArea) {
  TriangleMesh mesh;
  mesh.positions = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(2, 0, 0), Vec3(1, 1, 0)};
  // Triangle 1 is degenerate (collinear corners), triangle 3 at the end as well.
  mesh.triangles = {{0, 1, 2}, {0, 1, 3}, {1, 4, 2}, {0, 3, 1}};
  const AreaSampler sampler(mesh);
  EXPECT_DOUBLE_EQ(sampler.total_area(), 1.0);
  EXPECT_EQ(sampler.triangle_for(0.0), 0);
  EXPECT_EQ(sampler.triangle_for(0.4999), 0);
  EXPECT_EQ(sampler.triangle_for(0.5001), 2);
  EXPECT_EQ(sampler.triangle_for(std::nextafter(1.0, 0.0)), 2);
  for (const auto& p : random_surface_points(mesh, 0, 2000, 1))
    EXPECT_TRUE(p.triangle == 0 || p.triangle == 2);

  TriangleMesh flat;
  flat.positions = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(2, 0, 0)};
  flat.triangles = {{0, 1, 2}};
  EXPECT_THROW(AreaSampler{flat}, Error);
  EXPECT_THROW(random_surface_points(icosphere(0), -1, 3, 1), Error);
}

} // namespace
} // namespace texsim::geom
