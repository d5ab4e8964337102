#pragma once
/// The regions of a pattern on distributed cells and their moments: connected regions of marked
/// cells labelled across ranks, and per region its cells, area, area-weighted first and second
/// moments of the cells' positions and border length, added exactly (par::labelled_sums_on_root)
/// so every figure built on them is the same bits on any number of ranks.
#include "geom/surface_cells.hpp"
#include "par/comm.hpp"

#include <Eigen/Core>

#include <array>
#include <cstdint>
#include <span>
#include <vector>

namespace texsim::pipelines::turk_rd {

/// The connected regions of the cells marked in `owned_marked` (one entry per owned cell): for
/// the owned cells and then the ghosts, the smallest global cell id of the region, -1 where
/// unmarked; the same labels on any number of ranks. Collective.
std::vector<std::int64_t> label_cell_regions(const par::Comm& comm, const geom::SurfaceCells& cells,
                                             std::span<const char> owned_marked);

struct RegionMoments {
  std::int64_t label = 0;
  std::int64_t cells = 0;
  double area = 0;
  std::array<double, 3> first{};  ///< area-weighted x, y, z
  std::array<double, 6> second{}; ///< area-weighted xx, xy, xz, yy, yz, zz
  /// Length of the border with cells of other labels (coupling x distance of each such pair, as
  /// Turk's cells share borders), 0 for a region without one.
  double perimeter = 0;
};

/// The area-weighted mean position of the region's cells.
Eigen::Vector3d centre_of(const RegionMoments& region);
/// The area-weighted covariance of the region's cells' positions.
Eigen::Matrix3d covariance_of(const RegionMoments& region);

/// Rank 0 gets every labelled region's moments in increasing label order; the other ranks get
/// nothing. `labels` as label_cell_regions gives them. Collective.
std::vector<RegionMoments> region_moments_on_root(const par::Comm& comm,
                                                  const geom::SurfaceCells& cells,
                                                  std::span<const std::int64_t> labels);

} // namespace texsim::pipelines::turk_rd
