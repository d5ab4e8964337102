#pragma once
/// Coefficient fields of the feature-preserving (anisotropic) geometric diffusion
///   dx/dt - a(x)^mu div( a(x)^(1-mu) D(x) grad x ) = 0
/// of Bajaj, Zhang, Xu (GMP 2008, eqs. 18-21), after Bajaj & Xu, "Anisotropic Diffusion of
/// Subdivision Surfaces and Functions on Surfaces", ACM TOG 22(1), 2003: the curvature-driven
/// diffusion tensor D, the mesh-density function a and its mass/stiffness weights, and the
/// gradient-driven tensor for diffusing a function on a fixed surface. All per vertex; the FEM
/// assembly interpolates them over the triangles. Serial unless stated, not collective.
#include "geom/curvature_tensor.hpp"
#include "geom/mesh_topology.hpp"
#include "geom/triangle_mesh.hpp"

#include <Eigen/Core>

#include <span>
#include <vector>

namespace texsim::geom {

/// Parameters of the curvature-driven tensor D (eq. 19).
struct FeatureDiffusionParams {
  double lambda = 1.0; ///< feature threshold on |curvature|, 1/model units; > 0
  double alpha = 1.0;  ///< diffusivity along e1 (direction of the larger curvature k1); >= 0
  double beta = 1.0;   ///< diffusivity along e2 (direction of k2); >= 0
  /// Weight the normal part by min(g(k1), g(k2)) instead of 1. The paper adds the normal
  /// component unchanged; on a polyhedral surface the P1 gradients of the triangles beside a crease
  /// lean out of the vertex's tangent plane, so an undamped normal part lets diffusion cross the
  /// crease and rounds it. On a smooth surface tangential gradients have no normal part, so the
  /// continuous equation is the same either way.
  bool damp_normal_component = false;
};

/// The edge-stopping function g of eq. 20: 1 for |s| <= lambda, else
/// 1 / (1 + (|s| - lambda)^2 / lambda^2). Even in s, continuous, decreasing in |s|, in (0, 1].
/// (The transcription's "(s - lambda)^2" would jump from 1 to 1/5 at s = -lambda and treat concave
/// features differently from convex ones; |s| is what makes the stated case split consistent.)
/// lambda > 0; throws texsim::Error otherwise.
double feature_stopping(double s, double lambda);

/// D = alpha g(k1) e1 e1^T + beta g(k2) e2 e2^T + c N N^T (eq. 19; c = 1, or min(g(k1), g(k2))
/// with damp_normal_component): diffusion across a sharp crease
/// (large |k| across it) is damped, along it and in flat or gently curved regions it is not.
/// Symmetric, positive semi-definite (definite when alpha, beta > 0). Dimensionless.
/// Throws texsim::Error when lambda <= 0 or alpha or beta < 0.
Eigen::Matrix3d feature_diffusion_tensor(const PrincipalCurvature& curvature,
                                         const FeatureDiffusionParams& params);

/// feature_diffusion_tensor() of every vertex, indexed like `curvatures`. OpenMP-parallel,
/// deterministic.
std::vector<Eigen::Matrix3d>
feature_diffusion_tensors(std::span<const PrincipalCurvature> curvatures,
                          const FeatureDiffusionParams& params);

/// The mesh-density function a(x) of eq. 18 at each vertex, dimensionless: the vertex's lumped
/// area (a third of its triangles' areas), averaged over its closed one-ring, divided by the mean
/// lumped area of the vertices that have triangles. So a = 1 on a uniform mesh, a > 1 where the
/// mesh is coarser and a < 1 where it is finer, unchanged by scaling the mesh; a ~ h^2 / mean(h^2)
/// for local edge length h. Vertices without triangles get 1. This is a reconstruction: the
/// papers at hand only call a(x) "a smooth function which is adaptive to the mesh density" and
/// defer to Bajaj & Xu 2003, whose definition could not be retrieved; a ~ local area makes
/// a^mu the local time scale and a^(1-mu) the local diffusivity grow with the local cell size.
std::vector<double> mesh_density_function(const TriangleMesh& mesh, const MeshTopology& topology);

/// The mean lumped area's parts over vertices [0, first_vertices) that have triangles: their sum
/// and count (a distributed surface adds its owned vertices' parts over the ranks).
struct LumpedAreaSum {
  double area = 0.0;
  std::int64_t vertices = 0;
};
LumpedAreaSum lumped_area_sum(const TriangleMesh& mesh, const MeshTopology& topology,
                              std::int32_t first_vertices);

/// mesh_density_function with the mean lumped area given (> 0).
std::vector<double> mesh_density_function(const TriangleMesh& mesh, const MeshTopology& topology,
                                          double mean_lumped_area);

/// Per-vertex weights of the discrete eq. 21: `mass` = a^-mu multiplies the mass matrix entries
/// (a(x)^-mu phi_i, phi_j), `stiffness` = a^(1-mu) multiplies D in (a^(1-mu) D grad phi_i, grad
/// phi_j). stiffness / mass = a for every mu.
struct DensityWeights {
  std::vector<double> mass;
  std::vector<double> stiffness;
};

/// Weights a^-mu and a^(1-mu) of every entry of `density` (each > 0), 0 <= mu <= 1. Throws
/// texsim::Error otherwise.
DensityWeights density_weights(std::span<const double> density, double mu);

/// Diffusion tensor for smoothing a scalar function f given per vertex on a fixed surface, edge-
/// enhancing after Bajaj & Xu's function diffusion: with m the unit surface gradient of f and N
/// the vertex normal, D_f = I - (1 - g(|grad f|)) m m^T, i.e. full diffusion along the level lines
/// of f and along N, diffusion across steps of f damped by g (feature_stopping with threshold
/// `lambda`, in units of f per model unit). grad f at a vertex is the area-weighted mean of the
/// P1 gradients of its triangles projected onto the tangent plane of the area-weighted vertex
/// normal (exact for f linear on a plane). Where grad f = 0, D_f = I. Symmetric, eigenvalues in
/// (0, 1]. `values` is indexed like mesh.positions; `topology` must be built from `mesh`.
/// OpenMP-parallel, deterministic.
std::vector<Eigen::Matrix3d> function_diffusion_tensors(const TriangleMesh& mesh,
                                                        const MeshTopology& topology,
                                                        std::span<const double> values,
                                                        double lambda);

} // namespace texsim::geom
