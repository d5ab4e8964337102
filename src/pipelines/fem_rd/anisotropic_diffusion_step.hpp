#pragma once
/// One semi-implicit step of the weighted anisotropic diffusion of eq. (21),
///   (w f^{n+1}, v) + tau (T grad f^{n+1}, grad v) = (w f^n, v),
/// for any number of fields sharing the coefficients: w = a^-mu (mass weight) and
/// T = a^(1-mu) D (tensor), given per local vertex. Used for the surface coordinates (D from
/// curvature) and for functions on the surface (D from the function's gradient).
#include "geom/distributed_mesh.hpp"
#include "geom/feature_diffusion.hpp"
#include "par/cg_solver.hpp"
#include "pipelines/fem_rd/p1_assembler.hpp"

#include <Eigen/Core>

#include <span>
#include <vector>

namespace texsim::pipelines::fem_rd {

class AnisotropicDiffusionStep {
public:
  AnisotropicDiffusionStep(const par::Comm& comm, const geom::DistributedMesh& mesh,
                           bool lumped_mass, double rtol);

  /// Builds the step's matrices from the density weights and per-vertex tensors (both indexed
  /// by local mesh vertex, valid at owned vertices and ghosts) on the mesh's current positions.
  /// Collective.
  void assemble(const geom::DensityWeights& weights, std::span<const Eigen::Matrix3d> tensors,
                double dt);

  /// Advances one field: `owned` (this rank's vertices) holds f^n on entry, f^{n+1} on return.
  /// Collective.
  void advance(std::span<double> owned);

  const par::SolveStats& solve_stats() const { return solver_.stats(); }

private:
  const geom::DistributedMesh& mesh_;
  bool lumped_mass_;
  P1Assembler assembler_;
  par::CgSolver solver_;
  par::PetscMat system_, weighted_mass_;
  par::PetscVec field_, rhs_;
};

} // namespace texsim::pipelines::fem_rd
