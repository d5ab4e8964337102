#pragma once
/// Turk's explicit reaction-diffusion on the cells of a SurfaceCells tiling (1991, Part Two):
///   c_i <- c_i + dt (D_s L_i(c) + R_s(c_i)),   L_i(c) = (abar / A_i) sum_j f_ij w_ij (c_j - c_i),
/// where w_ij = border length / centre distance (the cells' coupling), A_i the cell area, abar the
/// mean cell area (so the operator is Turk's grid Laplacian in units of one cell, and his
/// parameters apply unchanged), and f_ij = (f_i + f_j) / 2 a diffusion scale that may vary over the
/// surface (the pseudo-zebra's wider stripes). Because f_ij w_ij is symmetric, diffusion conserves
/// sum_i A_i c_i exactly up to round-off.
///
/// The reaction R_s = C2 c + C3 comes from any fem_rd::ReactionModel (Turing spots, Meinhardt
/// stripes, user expressions), evaluated on cache-sized blocks of cells. Frozen cells keep their
/// values (Turk's initiators and cascades). The state of all species of a cell is one block of a
/// par::GhostedVector; neighbours are summed in id order, so every rank count gives the same bits.
#include "geom/surface_cells.hpp"
#include "par/comm.hpp"
#include "par/ghosted_vector.hpp"
#include "rd/reaction_model.hpp"
#include "rd/turing_spots_model.hpp"

#include <memory>
#include <span>
#include <string>
#include <vector>

namespace texsim::pipelines::turk_rd {

class CellRdSolver {
public:
  /// `diffusion_scale` holds f at every owned cell. Starts from the model's initial state. A `dt`
  /// above max_stable_dt() is split into substeps() explicit substeps of at most
  /// `stability_safety` * max_stable_dt() each. Collective.
  CellRdSolver(const par::Comm& comm, const geom::SurfaceCells& cells,
               const rd::ReactionModel& model, std::span<const double> diffusion_scale, double dt,
               double stability_safety = kDefaultStabilitySafety);

  /// Fraction of the stability limit a substep takes when dt exceeds the limit.
  static constexpr double kDefaultStabilitySafety = 0.9;

  std::size_t species_count() const { return names_.size(); }
  const std::vector<std::string>& species_names() const { return names_; }
  double dt() const { return dt_; }

  /// Values of species s at the owned cells.
  std::vector<double> owned_values(std::size_t s) const;
  /// Replaces species s at the owned cells. Collective (refreshes ghosts).
  void set_owned_values(std::size_t s, std::span<const double> owned);
  /// Owned cells with a nonzero entry keep their values in step().
  void set_frozen(std::vector<char> frozen);
  std::size_t frozen_count() const;

  /// Largest dt for which the explicit diffusion stays stable and positive: the update of a cell is
  /// a convex combination of its own and its neighbours' values when dt D_s sum_j weight_ij <= 1.
  double max_stable_dt() const { return max_stable_dt_; }
  /// Explicit substeps per step: 1 when dt <= max_stable_dt(), else
  /// ceil(dt / (stability_safety * max_stable_dt())).
  std::int64_t substeps() const { return substeps_; }
  /// dt / substeps(): the explicit step actually taken.
  double substep_dt() const { return substep_dt_; }

  /// One step from time t to t + dt: substeps() explicit updates of substep_dt(). Collective.
  void step(double t);

  /// sum_i A_i c_i over all cells. Collective.
  double integral(std::size_t s) const;

private:
  /// Cell updates of cells [begin, begin + count): the stencil and the reaction. `Species` > 0
  /// fixes the species count at compile time (the common systems), 0 reads it at run time.
  /// One thread's buffers for a block, kept across steps (no allocation per step).
  struct BlockScratch {
    std::vector<std::vector<double>> state;           ///< [species][cell of the block]
    std::vector<std::span<const double>> state_spans; ///< views of `state` for the model
    std::vector<rd::SpeciesCoefficients> coefficients;
    std::vector<double> laplacian; ///< for run-time species counts
  };
  /// With `Pointwise` a model type with vertex_coefficients() (Turing spots), the reaction is
  /// evaluated cell by cell inside the stencil loop; with void, through coefficients() on the
  /// block. Both give the same bits.
  template <int Species, typename Pointwise = void>
  void update_block(std::int32_t begin, std::int32_t count, double t, BlockScratch& scratch,
                    const Pointwise* pointwise = nullptr) const;
  /// The stencil rearranged for update_block: see build_lane_groups().
  void build_lane_groups();
  /// The model's C2 and C3 for the block's cells into scratch.coefficients.
  void evaluate_block(std::int32_t begin, std::int32_t count, double t,
                      BlockScratch& scratch) const;
  /// One explicit update of substep_dt_ from time t. Collective.
  void substep(double t);

  const par::Comm& comm_;
  const geom::SurfaceCells& cells_;
  const rd::ReactionModel& model_;
  std::vector<std::string> names_;
  double dt_;
  double max_stable_dt_ = 0;
  std::int64_t substeps_ = 1;
  double substep_dt_;
  std::vector<double> rates_;        ///< D_s of each species
  std::vector<double> lower_bounds_; ///< per species
  std::vector<double> weights_;      ///< (abar / A_i) f_ij w_ij, parallel to the stencil CSR
  /// The stencil by groups of a block's cells of like degree, their lists side by side
  /// (build_lane_groups); group_cells_ holds each group's kLanes cells.
  std::vector<std::int64_t> group_offsets_;
  std::vector<std::int32_t> group_widths_;
  std::vector<std::int32_t> group_cells_;
  std::vector<std::int32_t> group_first_value_; ///< neighbour index x species
  std::vector<double> group_weight_;
  std::vector<std::int64_t> ids_; ///< owned cell ids (random substrate keys)
  std::vector<double> xyz_;       ///< owned cell centres
  std::vector<double> substrate_; ///< the model's random substrate per owned cell (or empty)
  std::vector<char> frozen_;
  std::unique_ptr<par::GhostedVector> current_, next_;
  std::vector<BlockScratch> scratch_; ///< one per OpenMP thread
  /// The model when it is Turing's spot system, whose reaction the step fuses into the stencil.
  const rd::TuringSpotsModel* turing_spots_ = nullptr;
};

} // namespace texsim::pipelines::turk_rd
