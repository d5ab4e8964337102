#include "geom/feature_diffusion.hpp"

#include <algorithm>

#include "core/error.hpp"
#include "geom/mesh_measures.hpp"
#include "geom/p1_matrices.hpp"

#include <Eigen/Geometry>

#include <cmath>
#include <cstddef>

namespace texsim::geom {

double feature_stopping(double s, double lambda) {
  TEXSIM_VERIFY(lambda > 0.0, "feature_stopping: lambda " << lambda << " must be positive");
  const double magnitude = std::abs(s);
  if (magnitude <= lambda) {
    return 1.0;
  }
  const double excess = (magnitude - lambda) / lambda;
  return 1.0 / (1.0 + excess * excess);
}

Eigen::Matrix3d feature_diffusion_tensor(const PrincipalCurvature& curvature,
                                         const FeatureDiffusionParams& params) {
  TEXSIM_VERIFY(params.alpha >= 0.0 && params.beta >= 0.0,
                "feature_diffusion_tensor: alpha " << params.alpha << " and beta " << params.beta
                                                   << " must be non-negative");
  const double g1 = feature_stopping(curvature.k1, params.lambda);
  const double g2 = feature_stopping(curvature.k2, params.lambda);
  const double normal_weight = params.damp_normal_component ? std::min(g1, g2) : 1.0;
  return params.alpha * g1 * curvature.e1 * curvature.e1.transpose() +
         params.beta * g2 * curvature.e2 * curvature.e2.transpose() +
         normal_weight * curvature.normal * curvature.normal.transpose();
}

std::vector<Eigen::Matrix3d>
feature_diffusion_tensors(std::span<const PrincipalCurvature> curvatures,
                          const FeatureDiffusionParams& params) {
  // Validate once up front so that no exception leaves the parallel region.
  feature_diffusion_tensor(PrincipalCurvature{}, params);
  const auto count = static_cast<std::int64_t>(curvatures.size());
  std::vector<Eigen::Matrix3d> tensors(curvatures.size());
#pragma omp parallel for schedule(static)
  for (std::int64_t v = 0; v < count; ++v) {
    tensors[v] = feature_diffusion_tensor(curvatures[v], params);
  }
  return tensors;
}

LumpedAreaSum lumped_area_sum(const TriangleMesh& mesh, const MeshTopology& topology,
                              std::int32_t first_vertices) {
  const Eigen::VectorXd lumped = lumped_mass(mesh);
  LumpedAreaSum sum;
  for (std::int32_t v = 0; v < first_vertices; ++v) {
    if (!topology.vertex_triangles().row(v).empty()) {
      sum.area += lumped(v);
      ++sum.vertices;
    }
  }
  return sum;
}

std::vector<double> mesh_density_function(const TriangleMesh& mesh, const MeshTopology& topology) {
  const LumpedAreaSum sum = lumped_area_sum(mesh, topology, mesh.num_vertices());
  if (sum.vertices == 0 || !(sum.area > 0.0)) {
    return std::vector<double>(static_cast<std::size_t>(mesh.num_vertices()), 1.0);
  }
  return mesh_density_function(mesh, topology, sum.area / static_cast<double>(sum.vertices));
}

std::vector<double> mesh_density_function(const TriangleMesh& mesh, const MeshTopology& topology,
                                          double mean_lumped_area) {
  TEXSIM_VERIFY(mean_lumped_area > 0.0,
                "mesh_density_function: mean lumped area " << mean_lumped_area);
  const std::int32_t num_vertices = mesh.num_vertices();
  const Eigen::VectorXd lumped = lumped_mass(mesh);
  const CsrAdjacency& neighbors = topology.vertex_neighbors();
  std::vector<double> density(static_cast<std::size_t>(num_vertices), 1.0);
  for (std::int32_t v = 0; v < num_vertices; ++v) {
    if (topology.vertex_triangles().row(v).empty()) {
      continue;
    }
    double ring_sum = lumped(v);
    for (const std::int32_t w : neighbors.row(v)) {
      ring_sum += lumped(w);
    }
    const double ring_mean = ring_sum / static_cast<double>(neighbors.row(v).size() + 1);
    density[v] = ring_mean / mean_lumped_area;
  }
  return density;
}

DensityWeights density_weights(std::span<const double> density, double mu) {
  TEXSIM_VERIFY(mu >= 0.0 && mu <= 1.0, "density_weights: mu " << mu << " outside [0, 1]");
  DensityWeights weights;
  weights.mass.resize(density.size());
  weights.stiffness.resize(density.size());
  for (std::size_t v = 0; v < density.size(); ++v) {
    const double a = density[v];
    TEXSIM_VERIFY(a > 0.0,
                  "density_weights: density " << a << " at vertex " << v << " must be positive");
    weights.mass[v] = std::pow(a, -mu);
    weights.stiffness[v] = std::pow(a, 1.0 - mu);
  }
  return weights;
}

std::vector<Eigen::Matrix3d> function_diffusion_tensors(const TriangleMesh& mesh,
                                                        const MeshTopology& topology,
                                                        std::span<const double> values,
                                                        double lambda) {
  TEXSIM_VERIFY(values.size() == mesh.positions.size(),
                "function_diffusion_tensors: " << values.size() << " values for "
                                               << mesh.positions.size() << " vertices");
  TEXSIM_VERIFY(lambda > 0.0,
                "function_diffusion_tensors: lambda " << lambda << " must be positive");
  const std::int32_t num_triangles = mesh.num_triangles();
  const std::int32_t num_vertices = mesh.num_vertices();

  // P1 gradient of f on each triangle, times the triangle's area (the averaging weight):
  // grad phi_i = n x e_i / (2 area) with e_i the side opposite corner i, counter-clockwise.
  std::vector<Vec3> weighted_gradients(static_cast<std::size_t>(num_triangles));
#pragma omp parallel for schedule(static)
  for (std::int32_t t = 0; t < num_triangles; ++t) {
    const Triangle& tri = mesh.triangles[t];
    const Vec3& p0 = mesh.positions[tri[0]];
    const Vec3& p1 = mesh.positions[tri[1]];
    const Vec3& p2 = mesh.positions[tri[2]];
    const Vec3 doubled_area_vector = (p1 - p0).cross(p2 - p0);
    const double doubled_area = doubled_area_vector.norm();
    if (!(doubled_area > 0.0)) {
      weighted_gradients[t] = Vec3::Zero();
      continue;
    }
    const Vec3 n = doubled_area_vector / doubled_area;
    const Vec3 sum = values[tri[0]] * n.cross(p2 - p1) + values[tri[1]] * n.cross(p0 - p2) +
                     values[tri[2]] * n.cross(p1 - p0);
    weighted_gradients[t] = 0.5 * sum; // gradient (sum / doubled_area) times area
  }

  const std::vector<Vec3> normals = vertex_normals(mesh);
  const CsrAdjacency& vertex_triangles = topology.vertex_triangles();
  std::vector<Eigen::Matrix3d> tensors(static_cast<std::size_t>(num_vertices));
#pragma omp parallel for schedule(static)
  for (std::int32_t v = 0; v < num_vertices; ++v) {
    Vec3 gradient = Vec3::Zero();
    double area = 0.0;
    for (const std::int32_t t : vertex_triangles.row(v)) {
      gradient += weighted_gradients[t];
      area +=
          triangle_area(mesh.positions[mesh.triangles[t][0]], mesh.positions[mesh.triangles[t][1]],
                        mesh.positions[mesh.triangles[t][2]]);
    }
    tensors[v] = Eigen::Matrix3d::Identity();
    if (!(area > 0.0)) {
      continue;
    }
    const Vec3& n = normals[v];
    gradient = (gradient - n * n.dot(gradient)) / area;
    const double magnitude = gradient.norm();
    if (magnitude > 0.0) {
      const Vec3 m = gradient / magnitude;
      tensors[v] -= (1.0 - feature_stopping(magnitude, lambda)) * m * m.transpose();
    }
  }
  return tensors;
}

} // namespace texsim::geom
