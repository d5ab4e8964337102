#pragma once
/// Feature-preserving smoothing of the surface itself, eqs. (18)-(21): one semi-implicit step
///   (a^-mu x^{n+1}, v) + tau (a^(1-mu) D grad x^{n+1}, grad v) = (a^-mu x^n, v)
/// for the three coordinates, with D the curvature-driven tensor of eq. (19) and a the mesh-density
/// function (geom/feature_diffusion.hpp), both evaluated on the surface at step n. The three
/// coordinates share one matrix and one preconditioner. `isotropic` replaces D by the identity
/// (plain mean-curvature-like smoothing, the comparison case). Functions on the surface are
/// smoothed the same way with the gradient-driven tensor (smooth_function).
#include "geom/distributed_mesh.hpp"
#include "geom/feature_diffusion.hpp"
#include "pipelines/fem_rd/anisotropic_diffusion_step.hpp"

#include <span>

namespace texsim::pipelines::fem_rd {

struct SmoothingOptions {
  double dt = 1e-4; ///< tau of eq. (21), model units^2
  /// lambda, alpha, beta of eqs. (19)-(20); the normal part damped at creases by default
  geom::FeatureDiffusionParams feature{1.0, 1.0, 1.0, true};
  double mu = 0.5;              ///< exponent of the density function, in [0, 1]
  bool isotropic = false;       ///< D = identity
  double function_lambda = 1.0; ///< edge threshold of function smoothing, field units per length
  bool lumped_mass = false;
  double rtol = 1e-10;
};

class GeometrySmoother {
public:
  GeometrySmoother(const par::Comm& comm, geom::DistributedMesh& mesh,
                   const SmoothingOptions& options);

  /// Moves every vertex by one step; afterwards each rank holds its part's new positions.
  /// Collective.
  void step();

  /// One edge-preserving smoothing step of a function on the (fixed) surface, with the tensor
  /// D_f of geom::function_diffusion_tensors: `owned` holds this rank's values, in and out.
  /// Collective.
  void smooth_function(std::span<double> owned);

  const par::SolveStats& solve_stats() const { return diffusion_.solve_stats(); }

private:
  geom::DensityWeights density_weights() const;

  par::Comm comm_;
  geom::DistributedMesh& mesh_;
  SmoothingOptions options_;
  AnisotropicDiffusionStep diffusion_;
};

} // namespace texsim::pipelines::fem_rd
