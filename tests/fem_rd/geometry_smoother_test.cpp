// Feature-preserving smoothing (eqs. 18-21): it removes noise from a sphere, and on a noisy box it
// keeps the 90-degree edges that isotropic smoothing of the same duration rounds off.
#include "core/rng.hpp"
#include "geom/generators.hpp"
#include "geom/mesh_measures.hpp"
#include "pipelines/fem_rd/geometry_smoother.hpp"
#include "support/gather_by_id.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>

namespace texsim::pipelines::fem_rd {
namespace {

double radius_std(const geom::TriangleMesh& mesh) {
  double sum = 0, sum_sq = 0;
  for (const auto& p : mesh.positions) {
    sum += p.norm();
    sum_sq += p.squaredNorm();
  }
  const double n = double(mesh.positions.size());
  return std::sqrt(std::max(0.0, sum_sq / n - (sum / n) * (sum / n)));
}

geom::TriangleMesh smooth(const geom::TriangleMesh& surface, const SmoothingOptions& options,
                          int steps) {
  const par::Comm comm = par::world();
  geom::DistributedMesh mesh(comm, surface, geom::PartitionMethod::kScotch);
  GeometrySmoother smoother(comm, mesh, options);
  for (int n = 0; n < steps; ++n)
    smoother.step();
  // Back to input order, to compare with the input mesh.
  std::vector<double> xyz;
  for (std::int32_t v = 0; v < mesh.owned_count(); ++v)
    xyz.insert(xyz.end(), mesh.mesh().positions[v].data(), mesh.mesh().positions[v].data() + 3);
  const auto all = test::gather_by_id(comm, mesh.owned_input_ids(), xyz, 3);
  geom::TriangleMesh result = surface;
  for (std::size_t v = 0; v < result.positions.size(); ++v)
    result.positions[v] = geom::Vec3(all[3 * v], all[3 * v + 1], all[3 * v + 2]);
  return result;
}

TEST(GeometrySmoother, NoisySphereRadiusSpreadFallsFiveFold) {
  const auto sphere = geom::icosphere(4);
  const auto noisy = geom::noisy(sphere, 0.3 * geom::mean_edge_length(sphere), 21);
  SmoothingOptions options;
  options.dt = 1e-3;
  options.feature.lambda = 20.0; // above the noise's curvature (about 5): smooth it all
  const auto smoothed = smooth(noisy, options, 10);
  const double before = radius_std(noisy), after = radius_std(smoothed);
  EXPECT_LT(after * 5, before) << "radius std " << before << " -> " << after;
}

// Angle (degrees) between the two triangles at mesh edges lying on the box's 12 edges.
double mean_angle_at_box_edges(const geom::TriangleMesh& input, const geom::TriangleMesh& moved) {
  const auto normals = geom::triangle_normals(moved);
  const auto on_box_edge = [&](std::int32_t v) {
    int extreme = 0;
    for (int axis = 0; axis < 3; ++axis)
      extreme += std::abs(std::abs(input.positions[v][axis]) - 0.5) < 1e-9;
    return extreme >= 2;
  };
  std::map<std::pair<std::int32_t, std::int32_t>, std::vector<std::int32_t>> edge_triangles;
  for (std::int32_t t = 0; t < input.num_triangles(); ++t)
    for (int i = 0; i < 3; ++i) {
      std::int32_t a = input.triangles[t][i], b = input.triangles[t][(i + 1) % 3];
      if (on_box_edge(a) && on_box_edge(b))
        edge_triangles[{std::min(a, b), std::max(a, b)}].push_back(t);
    }
  double sum = 0;
  int count = 0;
  for (const auto& [edge, triangles] : edge_triangles) {
    const double cosine = normals[triangles[0]].dot(normals[triangles[1]]);
    sum += std::acos(std::clamp(cosine, -1.0, 1.0)) * 180.0 / M_PI;
    ++count;
  }
  return sum / count;
}

// RMS distance of the face-interior vertices from their face's plane: the noise left on the faces.
double face_noise(const geom::TriangleMesh& input, const geom::TriangleMesh& moved) {
  double sum_sq = 0;
  int count = 0;
  for (std::int32_t v = 0; v < input.num_vertices(); ++v) {
    int axis = -1, extreme = 0;
    for (int a = 0; a < 3; ++a)
      if (std::abs(std::abs(input.positions[v][a]) - 0.5) < 1e-9) {
        axis = a;
        ++extreme;
      }
    if (extreme != 1)
      continue;
    const double offset = std::abs(moved.positions[v][axis]) - 0.5;
    sum_sq += offset * offset;
    ++count;
  }
  return std::sqrt(sum_sq / count);
}

TEST(GeometrySmoother, KeepsBoxEdgesSharpWhereIsotropicSmoothingRoundsThem) {
  const auto box = geom::box(geom::Vec3(1, 1, 1), 16);
  const auto noisy = geom::noisy(box, 0.1 * geom::mean_edge_length(box), 5);
  SmoothingOptions anisotropic;
  anisotropic.dt = 4e-4;
  anisotropic.feature.lambda = 1.0; // below the edges' curvature (about 25), above the noise's
  SmoothingOptions isotropic = anisotropic;
  isotropic.isotropic = true;
  const auto kept = smooth(noisy, anisotropic, 10);
  const auto rounded = smooth(noisy, isotropic, 10);
  const double noisy_angle = mean_angle_at_box_edges(box, noisy);
  const double sharp = mean_angle_at_box_edges(box, kept);
  const double round = mean_angle_at_box_edges(box, rounded);
  EXPECT_GT(noisy_angle, 80.0);
  EXPECT_NEAR(sharp, 90.0, 8.0) << "noisy " << noisy_angle << ", isotropic " << round;
  EXPECT_LT(round, 45.0) << "noisy " << noisy_angle << ", anisotropic " << sharp;
  // And the faces were denoised, not left alone.
  EXPECT_LT(face_noise(box, kept) * 3, face_noise(box, noisy));
}

} // namespace
} // namespace texsim::pipelines::fem_rd

namespace texsim::pipelines::fem_rd {
namespace {

// Smooths a noisy step function on the unit sphere (1 above the equator, 0 below) and returns
// the mean jump across the equator (over vertex pairs straddling it) and the noise left away
// from it.
std::pair<double, double> smoothed_step(double function_lambda, int steps) {
  const par::Comm comm = par::world();
  const auto sphere = geom::icosphere(4);
  geom::DistributedMesh mesh(comm, sphere, geom::PartitionMethod::kMorton);
  SmoothingOptions options;
  options.dt = 2e-3;
  options.function_lambda = function_lambda;
  GeometrySmoother smoother(comm, mesh, options);
  const CounterRng rng(3, 1);
  std::vector<double> owned(mesh.owned_count());
  for (std::int32_t v = 0; v < mesh.owned_count(); ++v) {
    owned[v] = (mesh.mesh().positions[v].z() > 0) + 0.1 * rng.uniform(-1, 1, mesh.input_id()[v], 0);
  }
  for (int n = 0; n < steps; ++n)
    smoother.smooth_function(owned);
  const auto f = test::gather_by_id(comm, mesh.owned_input_ids(), owned);
  double jump = 0, noise = 0;
  int pairs = 0, far = 0;
  const geom::MeshTopology topology(sphere);
  for (const auto& edge : topology.edges()) {
    const double za = sphere.positions[edge[0]].z(), zb = sphere.positions[edge[1]].z();
    if ((za > 0) != (zb > 0)) {
      jump += std::abs(f[edge[0]] - f[edge[1]]);
      ++pairs;
    } else if (std::min(std::abs(za), std::abs(zb)) > 0.3) {
      noise += std::abs(f[edge[0]] - f[edge[1]]);
      ++far;
    }
  }
  return {jump / pairs, noise / far};
}

TEST(FunctionSmoothing, RemovesNoiseButKeepsTheStepThatIsotropicSmoothingBlurs) {
  const auto [input_jump, input_noise] = smoothed_step(0.5, 0);
  const auto [kept_jump, kept_noise] = smoothed_step(0.5, 10); // lambda below the step's slope
  const auto [blurred_jump, blurred_noise] = smoothed_step(1e6, 10); // g = 1: isotropic
  EXPECT_GT(input_jump, 0.9);
  EXPECT_GT(kept_jump, 0.45) << "isotropic: " << blurred_jump;
  EXPECT_LT(blurred_jump * 3, kept_jump);
  EXPECT_LT(kept_noise * 2, input_noise);
  EXPECT_LT(blurred_noise * 5, input_noise);
}

} // namespace
} // namespace texsim::pipelines::fem_rd
