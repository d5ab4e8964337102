#pragma once
/// Turk's rendering of a cell pattern (Turk 1991, Part Two "Rendering"): the value at a surface
/// point P is the weighted average of the values of the cells Q within a radius R,
///
///   v(P) = sum_Q w(|P - Q| / R) v_Q / sum_Q w(|P - Q| / R),   w(d) = 2d^3 - 3d^2 + 1 (d < 1), 0,
///
/// a smooth cubic falloff (w(0) = 1, w(1) = 0, w'(0) = w'(1) = 0). The weights are computed once
/// and kept as sparse rows, so rendering each frame of a simulation is one sparse product.
#include "geom/triangle_mesh.hpp"

#include <cstdint>
#include <span>
#include <vector>

namespace texsim::pipelines::turk_rd {

class PatternSampler {
public:
  /// Weights from every target point to the cells within `radius` (model units, > 0). `cells` and
  /// `cell_ids` are parallel arrays; the ids (e.g. global cell ids, ghosts included) must be unique
  /// and fix the order in which each target's sum is taken, so the result does not depend on the
  /// order of `cells`. A target with no cell within the radius takes its nearest cell's value
  /// (ties: the smallest id). Needs at least one cell unless there are no targets. OpenMP,
  /// deterministic; not collective. Throws Error for inconsistent input.
  PatternSampler(std::span<const geom::Vec3> targets, std::span<const geom::Vec3> cells,
                 std::span<const std::int64_t> cell_ids, double radius);

  /// out[i] = weighted average at target i of `cell_values` (indexed like the constructor's
  /// `cells`); out.size() == targets(). OpenMP, deterministic (the same bits for any thread count
  /// and any order of the cells).
  void sample(std::span<const double> cell_values, std::span<double> out) const;

  /// Convenience: sample() into a new vector.
  std::vector<double> sample(std::span<const double> cell_values) const;

  std::size_t targets() const { return row_start_.size() - 1; }
  std::size_t cells() const { return cell_count_; }
  /// Stored weights per target (a nearest-cell fallback counts one); 0 without targets.
  double mean_cells_per_target() const;
  /// Targets with no cell within the radius, which took their nearest cell's value: many of them
  /// mean the radius is too small for the cell spacing.
  std::size_t nearest_cell_targets() const { return nearest_cell_targets_; }

  /// Row i of the weights: target i's cells (indices into `cells`, in increasing id order) and
  /// their normalised weights (summing to 1 up to rounding).
  std::span<const std::uint32_t> row_cells(std::size_t target) const;
  std::span<const double> row_weights(std::size_t target) const;

private:
  std::size_t cell_count_ = 0;
  std::size_t nearest_cell_targets_ = 0;
  std::vector<std::size_t> row_start_{0}; ///< CSR offsets, targets() + 1 entries
  std::vector<std::uint32_t> columns_;    ///< cell index per weight
  std::vector<double> weights_;           ///< w / sum w per row
};

/// Turk's falloff w(d) = 2d^3 - 3d^2 + 1 for 0 <= d < 1, 0 for d >= 1 (d = distance / radius).
double turk_falloff(double d);

} // namespace texsim::pipelines::turk_rd
