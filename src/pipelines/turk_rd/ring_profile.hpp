#pragma once
/// Whether a cascade's marks form rings (Turk's rosettes: dark spots around a lighter centre):
/// the connected regions of the cells in `regions` (the large spots a first stage laid down), and
/// in each, how much of the area at a given distance from the region's centre the `marks` (the
/// later stage's dark spots) cover, distances in units of the region's equivalent radius
/// R = sqrt(area / pi). Rings cover the rim more than the centre; spots that fill their region
/// cover both alike.
#include "geom/surface_cells.hpp"
#include "par/comm.hpp"

#include <array>
#include <span>

namespace texsim::pipelines::turk_rd {

/// Distance bins of 0.25 R: [0, 0.25 R), ..., [1.25 R, 1.5 R) and beyond in the last.
inline constexpr int kRingBins = 6;
/// Regions of fewer cells are left out (fragments have no centre and rim to speak of).
inline constexpr int kRingMinCells = 8;

struct RingProfile {
  int regions = 0; ///< regions measured (at least kRingMinCells cells)
  /// Marked fraction of the area in each distance bin, over every measured region together.
  std::array<double, kRingBins> marked_by_radius{};
  double centre_marked = 0; ///< marked fraction within 0.5 R of the centres
  double rim_marked = 0;    ///< marked fraction from 0.75 R to 1.25 R
  /// Mean over the regions of the fraction of the rim's 8 angular sectors (around the centre, in
  /// the plane of the region's two principal axes) that hold a mark: about 1 for a closed ring
  /// of marks, 1/8 to 1/4 for one mark beside the centre, 0 for marks only at the centre.
  double rim_sectors_marked = 0;
};

/// `in_region` and `marked` hold one entry per owned cell. A region's centre is the area-weighted
/// mean of its cells' positions and distances are straight-line (the regions are small against
/// the surface's curvature radius). Sums are sliced (par::SliceGrids) and the region table is
/// O(regions), so the profile is the same bits on any number of ranks and no rank holds every
/// cell. Every rank gets the result. Collective.
RingProfile measure_rings(const par::Comm& comm, const geom::SurfaceCells& cells,
                          std::span<const char> in_region, std::span<const char> marked);

} // namespace texsim::pipelines::turk_rd
