#pragma once
/// Where the samples of one level's neighbourhood N(p) lie (Wei-Levoy Table 1, Fig. 5 (a)): an
/// R x C block around the vertex at the level's spacing d, the centre left out (noncausal
/// neighbourhoods read the whole block but not the value being chosen), and with two levels a
/// ceil(R/2) x ceil(C/2) block on the coarser level at spacing 2d. The same offsets describe an
/// exemplar neighbourhood in pixels, so the mesh and the image are read by one layout.
#include "pipelines/surface_synthesis/surface_synthesis_settings.hpp"

#include <Eigen/Core>

#include <vector>

namespace texsim::pipelines::surface_synthesis {

/// The two passes of Wei-Levoy's synthesis order (Section 3.2).
enum class Pass {
  extrapolate = 1, ///< pass 1: the coarser part only
  refine = 2,      ///< pass 2: current and coarser parts
};

struct NeighbourhoodTemplate {
  /// (dx, dy) pixel offsets of the current part, row by row, centre excluded: x to the right,
  /// y down as in images.
  std::vector<Eigen::Vector2d> current;
  /// (ox, oy) offsets on the coarser level in its pixels (half-integers when the block has an
  /// even side), about the parent position (x / 2, y / 2). Empty on a one-level shape.
  std::vector<Eigen::Vector2d> coarser;

  /// The layout of `shape`; `coarser_exists` false on the coarsest level.
  static NeighbourhoodTemplate from_shape(const NeighbourhoodShape& shape, bool coarser_exists);

  /// Samples read in a pass (pass 1 reads the coarser part only).
  std::size_t samples(Pass pass) const {
    return (pass == Pass::refine ? current.size() : 0) + coarser.size();
  }
  /// Flattened positions on the tangent plane (s = +x, t = up = -y) at spacing d: the current
  /// part at d, the coarser part at 2d.
  std::vector<Eigen::Vector2d> current_positions(double d) const;
  std::vector<Eigen::Vector2d> coarser_positions(double d) const;
};

} // namespace texsim::pipelines::surface_synthesis
