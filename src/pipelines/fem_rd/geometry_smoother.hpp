#pragma once
/// Feature-preserving smoothing of the surface itself, eqs. (18)-(21): one semi-implicit step
///   (a^-mu x^{n+1}, v) + tau (a^(1-mu) D grad x^{n+1}, grad v) = (a^-mu x^n, v)
/// for the three coordinates, with D the curvature-driven tensor of eq. (19) and a the mesh-density
/// function (geom/feature_diffusion.hpp), both evaluated on the surface at step n. The three
/// coordinates share one matrix and one preconditioner. `isotropic` replaces D by the identity
/// (plain mean-curvature-like smoothing, the comparison case).
#include "geom/distributed_mesh.hpp"
#include "geom/feature_diffusion.hpp"
#include "par/cg_solver.hpp"
#include "pipelines/fem_rd/p1_assembler.hpp"

namespace texsim::pipelines::fem_rd {

struct SmoothingOptions {
  double dt = 1e-4; ///< tau of eq. (21), model units^2
  /// lambda, alpha, beta of eqs. (19)-(20); the normal part damped at creases by default
  geom::FeatureDiffusionParams feature{1.0, 1.0, 1.0, true};
  double mu = 0.5;        ///< exponent of the density function, in [0, 1]
  bool isotropic = false; ///< D = identity
  bool lumped_mass = false;
  double rtol = 1e-10;
};

class GeometrySmoother {
public:
  GeometrySmoother(const par::Comm& comm, geom::DistributedMesh& mesh,
                   const SmoothingOptions& options);

  /// Moves every vertex by one step; afterwards every rank holds the new positions. Collective.
  void step();

  const par::SolveStats& solve_stats() const { return solver_.stats(); }

private:
  par::Comm comm_;
  geom::DistributedMesh& mesh_;
  SmoothingOptions options_;
  P1Assembler assembler_;
  par::CgSolver solver_;
  par::PetscMat system_, weighted_mass_;
  par::PetscVec coordinate_, rhs_;
};

} // namespace texsim::pipelines::fem_rd
