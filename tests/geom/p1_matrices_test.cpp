#include "geom/generators.hpp"
#include "geom/mesh_measures.hpp"
#include "geom/p1_matrices.hpp"

#include <Eigen/Geometry>
#include <gtest/gtest.h>

#include <cmath>

namespace texsim::geom {
namespace {

/// A jittered 6x6-vertex grid on a tilted plane through the origin, with its unit normal.
TriangleMesh tilted_patch(Vec3& normal) {
  const Vec3 s = Vec3(1, 0.3, -0.2).normalized();
  const Vec3 t = s.cross(Vec3(0.1, 0.2, 1)).normalized();
  normal = s.cross(t);
  TriangleMesh mesh;
  const int n = 5;
  for (int i = 0; i <= n; ++i) {
    for (int j = 0; j <= n; ++j) {
      const bool interior = i > 0 && i < n && j > 0 && j < n;
      const double di = interior ? 0.2 * std::sin(7.0 * i + 3.0 * j) : 0.0;
      const double dj = interior ? 0.2 * std::cos(5.0 * i - 2.0 * j) : 0.0;
      mesh.positions.push_back((i + di) * s + (j + dj) * t);
    }
  }
  for (int i = 0; i < n; ++i) {
    for (int j = 0; j < n; ++j) {
      const int a = i * (n + 1) + j;
      mesh.triangles.push_back({a, a + n + 1, a + n + 2});
      mesh.triangles.push_back({a, a + n + 2, a + 1});
    }
  }
  return mesh;
}

TEST(P1Matrices, LocalMassAndStiffnessOfRightTriangle) {
  const Vec3 a(0, 0, 0), b(1, 0, 0), c(0, 1, 0);
  const auto m = local_mass(a, b, c);
  EXPECT_DOUBLE_EQ(m(0, 0), 0.5 / 6.0);
  EXPECT_DOUBLE_EQ(m(0, 1), 0.5 / 12.0);
  const auto k = local_stiffness(a, b, c);
  // Off-diagonal entries are -cot(opposite angle)/2: 90 degrees at a, 45 at b and c.
  EXPECT_NEAR(k(1, 2), 0.0, 1e-15);
  EXPECT_DOUBLE_EQ(k(0, 1), -0.5);
  EXPECT_DOUBLE_EQ(k(0, 2), -0.5);
  EXPECT_DOUBLE_EQ(k(0, 0), 1.0);
  EXPECT_TRUE(k.isApprox(k.transpose()));
}

TEST(P1Matrices, MassSumsToAreaAndStiffnessRowsToZero) {
  const auto mesh = icosphere(3, 1.7);
  const auto mass = assemble_mass(mesh);
  const auto stiffness = assemble_stiffness(mesh);
  const double area = total_area(mesh);
  EXPECT_NEAR(Eigen::MatrixXd(mass).sum(), area, 1e-12 * area);
  EXPECT_NEAR(lumped_mass(mesh).sum(), area, 1e-12 * area);
  const Eigen::VectorXd ones = Eigen::VectorXd::Ones(mesh.num_vertices());
  EXPECT_LT((stiffness * ones).cwiseAbs().maxCoeff(), 1e-12);
  EXPECT_LT((Eigen::MatrixXd(stiffness) - Eigen::MatrixXd(stiffness).transpose()).norm(), 1e-12);
  // Lumped mass is the row sum of the consistent mass.
  EXPECT_LT((mass * ones - lumped_mass(mesh)).cwiseAbs().maxCoeff(), 1e-14);
}

TEST(P1Matrices, StiffnessGivesExactDirichletEnergyOfLinearFunction) {
  Vec3 normal;
  const auto mesh = tilted_patch(normal);
  const Vec3 g(0.7, -1.3, 2.1);
  Eigen::VectorXd u(mesh.num_vertices());
  for (std::int32_t v = 0; v < mesh.num_vertices(); ++v) {
    u[v] = g.dot(mesh.positions[v]) + 0.4;
  }
  const Vec3 tangential = g - g.dot(normal) * normal;
  const double exact = tangential.squaredNorm() * total_area(mesh);
  const double energy = u.dot(assemble_stiffness(mesh) * u);
  EXPECT_NEAR(energy, exact, 1e-12 * exact);
  // Mass of a constant is the area; of u, the exact integral of u^2 for a linear u.
  const Eigen::VectorXd ones = Eigen::VectorXd::Ones(mesh.num_vertices());
  EXPECT_NEAR(ones.dot(assemble_mass(mesh) * ones), total_area(mesh), 1e-12);
}

TEST(P1Matrices, RayleighQuotientOfFirstSphericalHarmonicApproachesTwo) {
  double previous_error = 1.0;
  for (int level = 2; level <= 4; ++level) {
    const auto mesh = icosphere(level);
    Eigen::VectorXd z(mesh.num_vertices());
    for (std::int32_t v = 0; v < mesh.num_vertices(); ++v) {
      z[v] = mesh.positions[v].z();
    }
    const double quotient = z.dot(assemble_stiffness(mesh) * z) / z.dot(assemble_mass(mesh) * z);
    const double error = std::abs(quotient - 2.0);
    EXPECT_LT(error, previous_error) << "level " << level;
    previous_error = error;
  }
  EXPECT_LT(previous_error, 5e-3);
}

} // namespace
} // namespace texsim::geom
