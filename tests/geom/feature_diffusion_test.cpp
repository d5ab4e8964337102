#include "geom/feature_diffusion.hpp"
#include "geom/generators.hpp"
#include "geom/mesh_topology.hpp"

#include "core/error.hpp"

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>
#include <gtest/gtest.h>

#include <cmath>

namespace texsim::geom {
namespace {

TEST(FeatureDiffusion, StoppingFunctionValues) {
  const double lambda = 0.8;
  EXPECT_EQ(feature_stopping(0.0, lambda), 1.0);
  EXPECT_EQ(feature_stopping(lambda, lambda), 1.0);
  EXPECT_EQ(feature_stopping(-lambda, lambda), 1.0);
  EXPECT_NEAR(feature_stopping(1.5 * lambda, lambda), 0.8, 1e-15);          // 1 / (1 + 1/4)
  EXPECT_NEAR(feature_stopping(2.0 * lambda, lambda), 0.5, 1e-15);          // 1 / (1 + 1)
  EXPECT_NEAR(feature_stopping(-2.0 * lambda, lambda), 0.5, 1e-15);         // even in s
  EXPECT_NEAR(feature_stopping(3.0 * lambda, lambda), 0.2, 1e-15);          // 1 / (1 + 4)
  EXPECT_NEAR(feature_stopping(lambda * (1.0 + 1e-8), lambda), 1.0, 1e-15); // continuous
  double previous = 1.0;
  for (double s = lambda; s < 20.0 * lambda; s += 0.1 * lambda) {
    const double g = feature_stopping(s, lambda);
    EXPECT_LE(g, previous);
    EXPECT_GT(g, 0.0);
    previous = g;
  }
  EXPECT_THROW(feature_stopping(1.0, 0.0), Error);
}

TEST(FeatureDiffusion, SphereBelowThresholdIsAlphaBetaInTangentPlane) {
  const double radius = 2.0;
  const auto mesh = icosphere(4, radius);
  const auto curvatures = principal_curvatures(mesh, MeshTopology(mesh));
  const FeatureDiffusionParams params{1.0 / radius + 0.1, 0.3, 0.8};
  const auto tensors = feature_diffusion_tensors(curvatures, params);
  ASSERT_EQ(tensors.size(), curvatures.size());
  for (std::size_t v = 0; v < tensors.size(); ++v) {
    const auto& c = curvatures[v];
    const Eigen::Matrix3d& d = tensors[v];
    ASSERT_LT((d * c.e1 - 0.3 * c.e1).norm(), 1e-12) << "vertex " << v;
    ASSERT_LT((d * c.e2 - 0.8 * c.e2).norm(), 1e-12) << "vertex " << v;
    ASSERT_LT((d * c.normal - c.normal).norm(), 1e-12) << "vertex " << v;
  }
  // With alpha = beta the tangential part no longer depends on the (arbitrary) umbilic frame.
  const auto isotropic = feature_diffusion_tensors(curvatures, {1.0, 0.6, 0.6});
  for (std::int32_t v = 0; v < mesh.num_vertices(); ++v) {
    const Vec3 n = mesh.positions[v].normalized();
    const Eigen::Matrix3d expected =
        0.6 * (Eigen::Matrix3d::Identity() - n * n.transpose()) + n * n.transpose();
    ASSERT_LT((isotropic[v] - expected).norm(), 1e-10) << "vertex " << v;
  }
}

TEST(FeatureDiffusion, SphereAboveThresholdIsDamped) {
  // k = 1/r = 0.5 = 2 lambda, so g = 1/2 in both principal directions.
  const auto mesh = icosphere(3, 2.0);
  const auto curvatures = principal_curvatures(mesh, MeshTopology(mesh));
  const auto tensors = feature_diffusion_tensors(curvatures, {0.25, 1.0, 1.0});
  for (std::size_t v = 0; v < tensors.size(); ++v) {
    EXPECT_NEAR(tensors[v].trace(), 0.5 + 0.5 + 1.0, 1e-10) << "vertex " << v;
  }
}

TEST(FeatureDiffusion, BoxEdgesDampDiffusionAcrossButNotAlong) {
  const int cells = 8;
  const double h = 1.0 / cells;
  const auto mesh = box(Vec3(1.0, 1.0, 1.0), cells);
  const auto curvatures = principal_curvatures(mesh, MeshTopology(mesh));
  const auto tensors = feature_diffusion_tensors(curvatures, {1.0, 1.0, 1.0});
  int edge_vertices = 0;
  int face_vertices = 0;
  for (std::int32_t v = 0; v < mesh.num_vertices(); ++v) {
    const Vec3& p = mesh.positions[v];
    int sharp_axes = 0;    // coordinates on a face plane
    int free_axis = -1;    // the coordinate running along the edge
    double corner_gap = 1; // distance of the free coordinate from the nearest box corner
    double edge_gap = 1;   // distance to the nearest face boundary
    for (int axis = 0; axis < 3; ++axis) {
      const double to_face = 0.5 - std::abs(p[axis]);
      if (to_face < 1e-12) {
        ++sharp_axes;
      } else {
        free_axis = axis;
        corner_gap = std::min(corner_gap, to_face);
        edge_gap = std::min(edge_gap, to_face);
      }
    }
    const Eigen::Matrix3d& d = tensors[v];
    if (sharp_axes == 2 && corner_gap > 1.5 * h) {
      ++edge_vertices;
      const Vec3 along = Vec3::Unit(free_axis);
      const Vec3 across = curvatures[v].normal.cross(along);
      EXPECT_NEAR(along.dot(d * along), 1.0, 1e-9) << "vertex " << v;
      EXPECT_LT(across.dot(d * across), 0.05) << "vertex " << v;
      EXPECT_NEAR(curvatures[v].normal.dot(d * curvatures[v].normal), 1.0, 1e-9);
    } else if (sharp_axes == 1 && edge_gap > 1.5 * h) {
      ++face_vertices; // flat: every triangle around lies in the face
      EXPECT_LT((d - Eigen::Matrix3d::Identity()).norm(), 1e-9) << "vertex " << v;
    }
  }
  EXPECT_EQ(edge_vertices, 12 * (cells - 3));
  EXPECT_EQ(face_vertices, 6 * (cells - 3) * (cells - 3));
}

TEST(FeatureDiffusion, TensorsAreSymmetricPositiveSemiDefinite) {
  const auto mesh = noisy(torus(1.0, 0.35, 48, 24), 0.01, 11);
  const auto curvatures = principal_curvatures(mesh, MeshTopology(mesh));
  const FeatureDiffusionParams params{2.0, 0.4, 1.7};
  for (const auto& d : feature_diffusion_tensors(curvatures, params)) {
    ASSERT_LT((d - d.transpose()).norm(), 1e-14);
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eigen(d);
    ASSERT_GT(eigen.eigenvalues().minCoeff(), -1e-12);
    ASSERT_LT(eigen.eigenvalues().maxCoeff(), 1.7 + 1e-12);
  }
  EXPECT_THROW(feature_diffusion_tensors(curvatures, {1.0, -0.1, 1.0}), Error);
}

TEST(FeatureDiffusion, DensityFollowsVertexAreaOnTorus) {
  // Lumped vertex areas of the torus grid grow like R + r cos v, whose mean over v is R, so
  // a -> 1 + (r / R) cos v as the grid is refined.
  const double major = 1.0;
  const double minor = 0.4;
  const int n_major = 96;
  const int n_minor = 48;
  const auto mesh = torus(major, minor, n_major, n_minor);
  const auto density = mesh_density_function(mesh, MeshTopology(mesh));
  for (int i = 0; i < n_major; ++i) {
    for (int j = 0; j < n_minor; ++j) {
      const double v = 2.0 * M_PI * j / n_minor;
      EXPECT_NEAR(density[static_cast<std::size_t>(i) * n_minor + j],
                  1.0 + minor / major * std::cos(v), 0.01);
    }
  }
  // Dimensionless: scaling the mesh leaves a unchanged.
  auto scaled = mesh;
  for (auto& p : scaled.positions) {
    p *= 3.7;
  }
  const auto scaled_density = mesh_density_function(scaled, MeshTopology(scaled));
  for (std::size_t v = 0; v < density.size(); ++v) {
    ASSERT_NEAR(scaled_density[v], density[v], 1e-12);
  }
}

TEST(FeatureDiffusion, DensityIsOneWithoutTriangles) {
  auto mesh = icosphere(2);
  mesh.positions.emplace_back(3.0, 0.0, 0.0);
  const auto density = mesh_density_function(mesh, MeshTopology(mesh));
  EXPECT_EQ(density.back(), 1.0);
}

TEST(FeatureDiffusion, DensityWeights) {
  const std::vector<double> density{0.5, 1.0, 2.0, 4.0};
  const auto explicit_mass = density_weights(density, 0.0);
  const auto explicit_stiffness = density_weights(density, 1.0);
  const auto mixed = density_weights(density, 0.3);
  for (std::size_t v = 0; v < density.size(); ++v) {
    EXPECT_DOUBLE_EQ(explicit_mass.mass[v], 1.0);
    EXPECT_DOUBLE_EQ(explicit_mass.stiffness[v], density[v]);
    EXPECT_DOUBLE_EQ(explicit_stiffness.mass[v], 1.0 / density[v]);
    EXPECT_DOUBLE_EQ(explicit_stiffness.stiffness[v], 1.0);
    EXPECT_DOUBLE_EQ(mixed.stiffness[v] / mixed.mass[v], density[v]);
    EXPECT_DOUBLE_EQ(mixed.mass[v], std::pow(density[v], -0.3));
  }
  EXPECT_THROW(density_weights(density, 1.5), Error);
  EXPECT_THROW(density_weights(std::vector<double>{1.0, 0.0}, 0.5), Error);
}

TEST(FeatureDiffusion, FunctionTensorOfLinearFunctionIsExact) {
  // f = 2x + y on the box: on the top face its surface gradient is (2, 1, 0), |grad f| = sqrt 5.
  const int cells = 6;
  const auto mesh = box(Vec3(1.0, 1.0, 1.0), cells);
  const MeshTopology topology(mesh);
  std::vector<double> values;
  for (const auto& p : mesh.positions) {
    values.push_back(2.0 * p.x() + p.y());
  }
  const double lambda = 1.0;
  const double g = feature_stopping(std::sqrt(5.0), lambda);
  ASSERT_LT(g, 0.5);
  const auto tensors = function_diffusion_tensors(mesh, topology, values, lambda);
  const Vec3 m = Vec3(2.0, 1.0, 0.0).normalized();
  const Eigen::Matrix3d expected = Eigen::Matrix3d::Identity() - (1.0 - g) * m * m.transpose();
  int checked = 0;
  for (std::int32_t v = 0; v < mesh.num_vertices(); ++v) {
    const Vec3& p = mesh.positions[v];
    const bool top_interior =
        p.z() > 0.5 - 1e-12 && std::abs(p.x()) < 0.5 - 1e-9 && std::abs(p.y()) < 0.5 - 1e-9;
    if (top_interior) {
      ++checked;
      EXPECT_LT((tensors[v] - expected).norm(), 1e-12) << "vertex " << v;
    }
  }
  EXPECT_EQ(checked, (cells - 1) * (cells - 1));

  // Below the threshold nothing is damped.
  for (const auto& d : function_diffusion_tensors(mesh, topology, values, 3.0)) {
    ASSERT_LT((d - Eigen::Matrix3d::Identity()).norm(), 1e-12);
  }
  EXPECT_THROW(function_diffusion_tensors(mesh, topology, std::vector<double>(3, 0.0), 1.0), Error);
}

} // namespace
} // namespace texsim::geom
