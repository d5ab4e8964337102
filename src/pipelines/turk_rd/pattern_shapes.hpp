#pragma once
/// What a pattern on the cells looks like: its spots or stripes are the connected regions of cells
/// above the mean value; a region's aspect is the ratio of its principal axes, and its elongation
/// its isoperimetric ratio
/// perimeter^2 / (4 pi area) (1 for a disc; about length / (pi width) for a long stripe), measured
/// with the cells' areas and shared border lengths, so it works on any surface (a stripe that
/// closes around a torus is as elongated as an open one).
#include "geom/surface_cells.hpp"
#include "par/comm.hpp"

#include <span>

namespace texsim::pipelines::turk_rd {

struct PatternShapes {
  int regions = 0;              ///< connected regions above the mean
  double mean_cells = 0;        ///< cells per region
  double median_elongation = 0; ///< over regions of at least 4 cells
  double max_elongation = 0;
  /// Mean over regions of at least 4 cells weighted by their cell counts: the elongation of a
  /// typical cell's region, not swayed by small fragments.
  double weighted_elongation = 0;
  /// Principal-axis aspect sqrt(lambda1 / lambda2) of a region: lambda1 >= lambda2 the two
  /// largest eigenvalues of the area-weighted covariance of its cells' positions (the third is
  /// the surface's normal direction). 1 for a disc, L / W for an L x W rectangle; a stripe that
  /// curves around the surface reads rounder than it is (a closed ring: 1), which is what
  /// elongation is for. Median and cell-weighted mean over regions of at least 4 cells.
  double median_aspect = 0;
  double weighted_aspect = 0;
};

/// Measured where the cells lie: the mean as a reproducible sum, the regions and their moments as
/// region_moments gives them, so no rank holds every cell and the figures are the same bits on
/// any number of ranks. Every rank gets the result. Collective.
PatternShapes measure_pattern(const par::Comm& comm, const geom::SurfaceCells& cells,
                              std::span<const double> owned_values);

} // namespace texsim::pipelines::turk_rd
