#pragma once
/// Pyramid solid synthesis (thesis section 3.3 and chapter 4; Lefebvre and Hoppe 2005): from one
/// voxel to a 2^L cube of exemplar coordinates, level by level: coordinate upsampling (eq. (1), or
/// eq. (5) under an anisometric field), hash-based jitter (eq. (2)), then voxel correction
/// (eqs. (3)-(4), or (6)-(7)) in order-independent subpasses.
///
/// Correction subpasses: the 8 voxel classes of the 2x2x2 parity lattice are corrected one after
/// another; within a class every voxel reads the state left by the previous subpass (new values
/// are buffered until the class is done), so the result does not depend on visiting order, thread
/// count or slab split, and halos are exchanged between subpasses.
#include "pipelines/solid_synthesis/anisometric_field.hpp"
#include "pipelines/solid_synthesis/coordinate_slab.hpp"
#include "pipelines/solid_synthesis/similarity_sets.hpp"
#include "vol/channel_grid.hpp"

#include <cstdint>
#include <functional>
#include <optional>
#include <vector>

namespace texsim::pipelines::solid_synthesis {

/// What the synthesis reads of the exemplar, per Gaussian-stack level s (feature spacing 2^s).
struct SynthesisExemplar {
  vol::Dims dims; ///< exemplar size; coordinates wrap modulo it
  std::vector<const vol::ChannelGrid*> features;
  /// Similarity sets per stack level; nullptr where the level is not corrected (the coarsest,
  /// constant levels).
  std::vector<const SimilaritySets*> sets;
};

struct SynthesisOptions {
  int levels = 7;      ///< L: the finest level is 2^L voxels a side
  double jitter = 0.7; ///< r_l of eq. (2) at every level but the finest
  /// r_L at the finest level. 0 by default: at spacing 1 a jitter of one voxel that the
  /// correction passes do not all undo stays as isolated speckles (bricks: 6.1% of the voxels
  /// continued by no neighbour with 0.7 there, 0.7% with 0). Lefebvre and Hoppe 2005 set r_l per
  /// level for the same reason.
  double finest_jitter = 0.0;
  int correction_passes = 2; ///< passes of 8 subpasses per level (the most, with min_improvement)
  /// When set: after the first pass, another pass runs only while the last one lowered the summed
  /// match distance by at least this fraction of the pass before (the error stopped falling:
  /// stop). The sums are exact fixed-point sums, so the decision is the same at any rank and
  /// thread count.
  std::optional<double> min_improvement;
  /// kappa: the distance of a candidate that does not continue its neighbour (similarity-set
  /// entries after the first) is scaled by 1 + kappa, so near ties go to coherent patches
  /// (Hertzmann et al.'s and Lefebvre-Hoppe's coherence parameter); 0: the thesis' plain minimum.
  double coherence = 0.0;
  std::uint64_t seed = 1; ///< key of the jitter hash
};

/// How one level went, for the run report.
struct LevelStats {
  int level = 0;
  int spacing = 0;     ///< h_l
  int stack_level = 0; ///< Gaussian-stack level whose features were matched
  bool corrected = false;
  /// Mean over the level's voxels of the squared appearance-space distance between N_S(p) and the
  /// chosen N_E(u) in the last pass (0 when not corrected).
  double mean_match_distance = 0.0;
  /// Halo exchanges the level made (before each correction subpass and after the last).
  int halo_exchanges = 0;
  int passes = 0; ///< correction passes run
  /// Mean match distance of each pass, as the fixed-point sums that decided when to stop.
  std::vector<double> pass_distances;
};

class PyramidSynthesizer {
public:
  /// `field` (may be null: isometric synthesis) must outlive the synthesizer.
  PyramidSynthesizer(const par::Comm& comm, SynthesisExemplar exemplar, SynthesisOptions options,
                     const AxesField* field);

  /// Level 0: a single voxel at exemplar coordinate 0, jittered. Collective.
  CoordinateSlab first_level(LevelStats& stats) const;
  /// Asked before each correction subpass; must give the same answer on every rank (it is called
  /// collectively). True abandons the level.
  using StopCheck = std::function<bool()>;

  /// The level after `parent`: upsampling, jitter and correction; nullopt when `stop` abandoned
  /// it. Collective.
  std::optional<CoordinateSlab> next_level(const CoordinateSlab& parent, LevelStats& stats,
                                           const StopCheck& stop = {}) const;

  /// h_l = 2^(L - l).
  int spacing(int level) const { return 1 << (options_.levels - level); }
  /// The stack level matched at pyramid level `level`: log2 h_l, capped at the coarsest.
  int stack_level(int level) const;
  const SynthesisOptions& options() const { return options_; }

private:
  void jitter(CoordinateSlab& slab, int level) const;
  /// A_l and A_l^-1 over the slab's planes and halo; none for isometric synthesis.
  std::optional<LevelJacobians> level_jacobians(const LevelLayout& layout) const;
  /// False when `stop` abandoned the correction between subpasses.
  bool correct(CoordinateSlab& slab, int level, const std::optional<LevelJacobians>& jacobians,
               LevelStats& stats, const StopCheck& stop = {}) const;
  /// c wrapped into the exemplar, fraction kept.
  Position wrapped(const Position& c) const;

  par::Comm comm_;
  SynthesisExemplar exemplar_;
  SynthesisOptions options_;
  const AxesField* field_;
};

/// Level of a slab: log2 of its size.
int level_of(const CoordinateSlab& slab);

} // namespace texsim::pipelines::solid_synthesis
