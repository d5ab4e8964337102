#include "geom/lscm_parameterization.hpp"

#include "core/error.hpp"
#include "geom/generators.hpp"
#include "geom/submesh.hpp"

#include <Eigen/Geometry>
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <string>
#include <vector>

namespace texsim::geom {
namespace {

/// Interior angle (radians) at `a` of the triangle a, b, c, in any dimension.
template <typename Vec> double corner_angle(const Vec& a, const Vec& b, const Vec& c) {
  const Vec u = b - a;
  const Vec v = c - a;
  return std::atan2(
      std::sqrt(std::max(0.0, u.squaredNorm() * v.squaredNorm() - u.dot(v) * u.dot(v))), u.dot(v));
}

double signed_area(const Eigen::Vector2d& a, const Eigen::Vector2d& b, const Eigen::Vector2d& c) {
  const Eigen::Vector2d u = b - a;
  const Eigen::Vector2d v = c - a;
  return 0.5 * (u.x() * v.y() - u.y() * v.x());
}

struct AngleComparison {
  double max_error = 0.0;  ///< radians
  double mean_error = 0.0; ///< radians
  int flipped = 0;         ///< uv triangles with non-positive signed area
};

AngleComparison compare_angles(const TriangleMesh& mesh, const std::vector<Eigen::Vector2d>& uv) {
  AngleComparison result;
  double sum = 0.0;
  for (const auto& tri : mesh.triangles) {
    if (signed_area(uv[tri[0]], uv[tri[1]], uv[tri[2]]) <= 0.0) {
      ++result.flipped;
    }
    for (int i = 0; i < 3; ++i) {
      const auto a = tri[i], b = tri[(i + 1) % 3], c = tri[(i + 2) % 3];
      const double error =
          std::abs(corner_angle(uv[a], uv[b], uv[c]) -
                   corner_angle(mesh.positions[a], mesh.positions[b], mesh.positions[c]));
      result.max_error = std::max(result.max_error, error);
      sum += error;
    }
  }
  result.mean_error = sum / (3.0 * mesh.num_triangles());
  return result;
}

/// An n x n grid of the unit square with irregularly jittered interior nodes (so the map is not
/// trivially axis-aligned), rotated rigidly into a tilted plane in 3D. Triangles are CCW about the
/// rotated +z axis.
TriangleMesh tilted_grid(int n) {
  TriangleMesh mesh;
  const Eigen::Matrix3d rotation =
      (Eigen::AngleAxisd(0.7, Eigen::Vector3d(1.0, 2.0, -0.5).normalized()) *
       Eigen::AngleAxisd(-1.1, Eigen::Vector3d::UnitZ()))
          .toRotationMatrix();
  const Vec3 offset(0.3, -2.0, 5.0);
  for (int j = 0; j <= n; ++j) {
    for (int i = 0; i <= n; ++i) {
      const bool interior = i > 0 && i < n && j > 0 && j < n;
      const double jitter = interior ? 0.2 / n : 0.0;
      const Vec3 flat((i + jitter * std::sin(3.0 * i + 7.0 * j)) / n,
                      (j + jitter * std::cos(5.0 * i - 2.0 * j)) / n, 0.0);
      mesh.positions.push_back(rotation * flat + offset);
    }
  }
  const auto id = [n](int i, int j) { return j * (n + 1) + i; };
  for (int j = 0; j < n; ++j) {
    for (int i = 0; i < n; ++i) {
      mesh.triangles.push_back({id(i, j), id(i + 1, j), id(i + 1, j + 1)});
      mesh.triangles.push_back({id(i, j), id(i + 1, j + 1), id(i, j + 1)});
    }
  }
  return mesh;
}

/// The triangles of a unit icosphere whose centroid satisfies `keep`, renumbered.
template <typename Keep> TriangleMesh icosphere_part(int level, Keep keep) {
  const auto sphere = icosphere(level);
  std::vector<int> part(sphere.triangles.size());
  for (std::size_t t = 0; t < part.size(); ++t) {
    const auto& tri = sphere.triangles[t];
    const Vec3 centroid =
        (sphere.positions[tri[0]] + sphere.positions[tri[1]] + sphere.positions[tri[2]]) / 3.0;
    part[t] = keep(centroid) ? 1 : 0;
  }
  return extract_part(sphere, part, 1).mesh;
}

TEST(LscmParameterization, FlatPatchIsMappedBySimilarity) {
  const auto grid = tilted_grid(12);
  const auto uv = lscm_parameterize(grid);
  ASSERT_EQ(uv.size(), grid.positions.size());
  const auto angles = compare_angles(grid, uv);
  EXPECT_LT(angles.max_error, 1e-6);
  EXPECT_EQ(angles.flipped, 0);
  // A similarity also keeps every length ratio: the uv edge lengths over the 3D ones are constant.
  const double scale = (uv[1] - uv[0]).norm() / (grid.positions[1] - grid.positions[0]).norm();
  EXPECT_GT(scale, 0.0);
  for (const auto& tri : grid.triangles) {
    for (int i = 0; i < 3; ++i) {
      const auto a = tri[i], b = tri[(i + 1) % 3];
      EXPECT_NEAR((uv[b] - uv[a]).norm(), scale * (grid.positions[b] - grid.positions[a]).norm(),
                  1e-6 * scale);
    }
  }
}

TEST(LscmParameterization, CurvedCapHasNoFlipsAndSmallAngleDistortion) {
  const auto cap = icosphere_part(3, [](const Vec3& c) { return c.z() > 0.1; });
  ASSERT_GT(cap.num_triangles(), 100);
  const auto uv = lscm_parameterize(cap);
  const auto angles = compare_angles(cap, uv);
  EXPECT_EQ(angles.flipped, 0);
  const double degree = std::numbers::pi / 180.0;
  EXPECT_LT(angles.mean_error, 2.5 * degree);
  EXPECT_LT(angles.max_error, 10.0 * degree);
}

TEST(LscmParameterization, RefusesMeshesThatAreNotDisks) {
  const auto expect_refused = [](const TriangleMesh& mesh, const std::string& what) {
    try {
      lscm_parameterize(mesh);
      ADD_FAILURE() << "no exception for " << what;
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find(what), std::string::npos) << e.what();
    }
  };
  expect_refused(icosphere(2), "0 boundary loops");
  expect_refused(icosphere_part(2, [](const Vec3& c) { return std::abs(c.z()) < 0.5; }),
                 "2 boundary loops");
  expect_refused(TriangleMesh{}, "no triangles");
}

} // namespace
} // namespace texsim::geom
