#pragma once
/// Which way a pattern's stripes run against a body axis (Turk's pseudo-zebra: stripes across the
/// body): in every cell the gradient of the pattern in the cell's tangent plane (least squares
/// over its neighbours, the plane spanned by them) against the axis projected onto that plane.
/// The share of the squared gradient along the projected axis, area-weighted, is 1 for stripes
/// straight across the axis, 0 for stripes along it and 1/2 for a labyrinth without a direction.
#include "geom/surface_cells.hpp"
#include "par/comm.hpp"

#include <span>

namespace texsim::pipelines::turk_rd {

/// sum(area (g . a_t)^2) / sum(area |g|^2 |a_t|^2) over the cells where the axis' tangent part
/// a_t is at least 0.1 of the unit axis; `owned_values` one per owned cell, `axis` nonzero. The
/// same bits on any number of ranks (reproducible sums, neighbours in id order). Collective.
double stripes_across_axis(const par::Comm& comm, const geom::SurfaceCells& cells,
                           std::span<const double> owned_values, const geom::Vec3& axis);

} // namespace texsim::pipelines::turk_rd
