#pragma once
/// The semi-implicit backward Euler step of eqs. (5)-(8) for every species of a ReactionModel on
/// a DistributedMesh:  (M_w + tau C0C1 K) u^{n+1} = M (u^n + tau (C3 + C2+ u^n)),
/// w = 1 - tau C2-, where C2 and C3 come from the state at step n, C2- = min(C2, 0) is treated
/// implicitly and C2+ = max(C2, 0) explicitly. Keeping the growing part explicit keeps the matrix
/// symmetric positive definite for any tau, which conjugate gradients (the paper's solver) needs;
/// the consistency of the scheme is unchanged (first order in tau either way). M is the P1 mass
/// matrix (consistent, or lumped as an option), K the stiffness matrix; both depend only on the
/// geometry and are rebuilt by rebuild_geometry(); each step recomputes only the weighted mass.
#include "geom/distributed_mesh.hpp"
#include "par/cg_solver.hpp"
#include "par/ghosted_vector.hpp"
#include "pipelines/fem_rd/p1_assembler.hpp"
#include "pipelines/fem_rd/reaction_model.hpp"

#include <memory>
#include <vector>

namespace texsim::pipelines::fem_rd {

struct RdOptions {
  double dt = 0.5;          ///< tau
  bool lumped_mass = false; ///< lumped instead of consistent mass
  double rtol = 1e-10;      ///< CG relative tolerance
};

class ReactionDiffusionSolver {
public:
  /// Sets every species to the model's initial state. Collective.
  ReactionDiffusionSolver(const par::Comm& comm, const geom::DistributedMesh& mesh,
                          const ReactionModel& model, const RdOptions& options);

  /// Recomputes mass and stiffness after the mesh moved. Collective.
  void rebuild_geometry();

  /// Advances every species from time t to t + dt. Collective.
  void step(double t);

  std::size_t species_count() const { return fields_.size(); }
  const std::vector<std::string>& species_names() const { return names_; }
  /// Owned then ghost values of species s.
  std::span<const double> local_values(std::size_t s) const { return fields_[s]->local(); }
  /// Replaces the owned values of species s (e.g. from a checkpoint). Collective.
  void set_owned_values(std::size_t s, std::span<const double> owned);

  /// The integral of species s over the surface, 1^T M u. Collective.
  double integral(std::size_t s) const;

  /// CG statistics over all species' solves so far.
  const par::SolveStats& solve_stats(std::size_t s) const { return solvers_[s]->stats(); }
  std::string solver_description() const { return solvers_.front()->description(); }

private:
  void refresh_vertex_data();
  void clamp_to_lower_bound(std::size_t s);

  par::Comm comm_;
  const geom::DistributedMesh& mesh_;
  const ReactionModel& model_;
  RdOptions options_;
  P1Assembler assembler_;
  std::vector<std::string> names_;
  std::vector<std::unique_ptr<par::GhostedVector>> fields_;
  std::vector<std::unique_ptr<par::CgSolver>> solvers_;
  std::vector<par::PetscMat> systems_; ///< M_w + tau C0C1 K, one per species
  par::PetscMat mass_;                 ///< M (unit weight)
  std::vector<double> stiffness_;      ///< K in pattern order
  par::PetscVec rhs_, explicit_part_, ones_;
  std::vector<std::int64_t> local_ids_; ///< input-mesh id of each local vertex
  std::vector<double> local_xyz_;       ///< position of each local vertex
  std::vector<SpeciesCoefficients> coefficients_;
};

} // namespace texsim::pipelines::fem_rd
