#pragma once
/// The semi-implicit backward Euler step of eqs. (5)-(8) for every species of a ReactionModel on
/// a DistributedMesh:  (M_w + tau C0C1 K) u^{n+1} = M (u^n + tau (C3 + C2+ u^n)),
/// w = 1 - tau C2-, where C2 and C3 come from the state at step n, C2- = min(C2, 0) is treated
/// implicitly and C2+ = max(C2, 0) explicitly. Keeping the growing part explicit keeps the matrix
/// symmetric positive definite for any tau, which conjugate gradients (the paper's solver) needs;
/// the consistency of the scheme is unchanged (first order in tau either way). M is the mass
/// matrix of the basis (P1 hats or Loop's C1 box splines, FemAssembler; consistent, or lumped as
/// an option), K the stiffness matrix; both depend only on the
/// geometry and are rebuilt by rebuild_geometry(); each step recomputes only the weighted mass.
///
/// Preconditioner: point Jacobi on the step matrix when CG + Jacobi converges within
/// kJacobiProbeLimit iterations on a probe solve of P = M + tau C0C1 K (clean meshes), else
/// algebraic multigrid (hypre's BoomerAMG: 4x fewer iterations than GAMG on the raw scans of
/// docs/fem_rd.md) built from P. P depends only on the geometry, so the hierarchy is
/// set up once per rebuild_geometry() and reused by every step (M_w >= M, so P stays a good
/// preconditioner of every step's matrix), and the choice and the hierarchy are the same after a
/// restart: runs stay reproducible byte for byte.
#include "geom/distributed_mesh.hpp"
#include "par/cg_solver.hpp"
#include "par/ghosted_vector.hpp"
#include "pipelines/fem_rd/diffusion_field.hpp"
#include "pipelines/fem_rd/fem_assembler.hpp"
#include "rd/reaction_model.hpp"

#include <nlohmann/json.hpp>

#include <memory>
#include <span>
#include <vector>

namespace texsim::pipelines::fem_rd {

/// The functions u is expanded in (eq. 7): P1 hats on the mesh, or the paper's C1 Loop box
/// splines with the mesh as control mesh (LoopAssembler).
enum class FemBasis { kP1, kLoop };

/// The preconditioner of the RD solves: chosen by a probe solve (kAuto) or fixed.
enum class RdPreconditioner { kAuto, kJacobi, kGamg, kBoomerAmg };

struct RdOptions {
  double dt = 0.5;                                           ///< tau
  bool lumped_mass = false;                                  ///< lumped instead of consistent mass
  double rtol = 1e-10;                                       ///< CG relative tolerance
  RdPreconditioner preconditioner = RdPreconditioner::kAuto; ///< fem_rd.solver.preconditioner
  FemBasis basis = FemBasis::kP1;                            ///< fem_rd.basis
};

class ReactionDiffusionSolver {
public:
  /// Sets every species to the model's initial state; `field` (fem_rd.diffusion) turns C0C1
  /// into a tensor for the species it names, none keeps every rate constant. Collective.
  ReactionDiffusionSolver(const par::Comm& comm, const geom::DistributedMesh& mesh,
                          const rd::ReactionModel& model, const RdOptions& options,
                          const std::optional<DiffusionFieldSettings>& field = std::nullopt);

  /// Recomputes mass and stiffness after the mesh moved. Collective.
  void rebuild_geometry();

  /// Advances every species from time t to t + dt. Collective.
  void step(double t);

  std::size_t species_count() const { return fields_.size(); }
  const std::vector<std::string>& species_names() const { return names_; }
  /// Owned then ghost values of species s: the coefficients u_i of eq. (7).
  std::span<const double> local_values(std::size_t s) const { return fields_[s]->local(); }
  /// Species s on the surface at the owned vertices and ghosts: the coefficients for P1, the
  /// limit values (Loop's limit mask) for Loop. Collective.
  std::vector<double> surface_values(std::size_t s) const;
  /// The surface's points at the owned vertices and ghosts: the mesh's for P1, its limit points
  /// for Loop. Not collective.
  std::vector<geom::Vec3> surface_points() const;
  /// Replaces the owned values of species s (e.g. from a checkpoint). Collective.
  void set_owned_values(std::size_t s, std::span<const double> owned);

  /// The integral of species s over the surface, 1^T M u. Collective.
  double integral(std::size_t s) const;

  /// CG statistics over all species' solves so far.
  const par::SolveStats& solve_stats(std::size_t s) const { return solvers_[s]->stats(); }
  std::string solver_description() const { return solvers_.front()->description(); }
  /// The preconditioner of the RD solves (fixed by the options or chosen by the probe).
  par::Preconditioner preconditioner() const { return preconditioner_; }
  /// The preconditioner in use, how it was chosen (the probe's iterations) and the CG iterations
  /// of every step so far (summed over species), for summary.json.
  nlohmann::json solver_metrics() const;

  /// Auto choice: Jacobi when its probe solve converges within this many iterations.
  static constexpr int kJacobiProbeLimit = 200;
  /// A step whose solves average more CG iterations than this logs a warning naming mesh.remesh.
  static constexpr int kWarnIterations = 200;

private:
  void refresh_vertex_data();
  /// Every species at the vertices that coefficient arrays cover (FemAssembler::
  /// coefficient_count): the ghosted vector's local part, or, for Loop's wider supports, the
  /// whole local mesh with the halo filled from the owners. Collective.
  std::vector<std::span<const double>> coefficient_state();
  /// Species s at every vertex of the local mesh, the halo's values from their owners.
  /// Collective.
  std::vector<double> on_whole_halo(std::size_t s) const;
  /// K with fem_rd.diffusion's tensors at the current geometry and state. Collective.
  void assemble_field_stiffness();
  void clamp_to_lower_bound(std::size_t s);
  /// Pattern-ordered values of M_w + tau D K_s (unit weight when `weight` is empty), K_s the
  /// stiffness of species s: with fem_rd.diffusion's tensors if they apply to it, except, when
  /// `geometry_only`, tensors that read the species (the probe and the AMG preconditioner
  /// depend on the geometry alone, so a restarted run makes the same ones).
  std::vector<double> system_values(std::span<const double> weight, std::size_t s,
                                    bool geometry_only) const;
  /// The diffusion rate of each species (constant per species), from one model evaluation.
  std::vector<double> species_diffusion();
  /// Applies options_.preconditioner; for kAuto runs the Jacobi probe. Collective.
  par::Preconditioner choose_preconditioner();
  /// P = M + tau D K of every species into preconditioning_. Collective.
  void assemble_preconditioners();
  /// Sums the step's iterations and warns once when they point at a badly shaped mesh.
  void record_step_iterations(long long iterations);

  par::Comm comm_;
  const geom::DistributedMesh& mesh_;
  const rd::ReactionModel& model_;
  RdOptions options_;
  std::unique_ptr<FemAssembler> assembler_;
  std::vector<std::string> names_;
  std::vector<std::unique_ptr<par::GhostedVector>> fields_;
  std::vector<std::unique_ptr<par::CgSolver>> solvers_;
  std::vector<par::PetscMat> systems_; ///< M_w + tau C0C1 K, one per species
  par::PetscMat mass_;                 ///< M (unit weight)
  std::vector<double> stiffness_;      ///< K in pattern order
  std::unique_ptr<DiffusionField> field_;
  std::vector<double> field_stiffness_; ///< K with fem_rd.diffusion's tensors, pattern order
  par::PetscVec rhs_, explicit_part_, ones_;
  std::vector<std::vector<double>> halo_state_; ///< Loop: each species on the whole local mesh
  std::vector<std::int64_t> local_ids_;         ///< input-mesh id of each coefficient vertex
  std::vector<double> local_xyz_;               ///< position of each local vertex
  std::vector<rd::SpeciesCoefficients> coefficients_;
  std::vector<double> diffusion_; ///< per species
  par::Preconditioner preconditioner_ = par::Preconditioner::kJacobi;
  int probe_iterations_ = -1; ///< Jacobi probe iterations (-1: no probe)
  bool probe_converged_ = false;
  std::vector<par::PetscMat> preconditioning_; ///< P per species (AMG only)
  std::vector<long long> step_iterations_;     ///< CG iterations of each step, summed over species
  bool warned_ = false;
  double mean_edge_length_ = 0; ///< of the mesh, for the warning
};

} // namespace texsim::pipelines::fem_rd
