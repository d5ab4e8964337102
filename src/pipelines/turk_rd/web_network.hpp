#pragma once
/// Whether a pattern is a reticulated network (Turk's giraffe: polygonal patches separated by a
/// thin connected web): the connected regions of the `web` cells and of the other cells (the
/// patches), the web's area and border length with the patches. A network has one web component
/// holding nearly all the web, many patches, and a web much thinner than the patches are wide;
/// spots on a background read as a wide web.
#include "geom/surface_cells.hpp"
#include "par/comm.hpp"

#include <span>

namespace texsim::pipelines::turk_rd {

struct WebNetwork {
  double web_area_fraction = 0;     ///< web area over the surface's
  int web_components = 0;           ///< connected regions of web cells
  double largest_web_fraction = 0;  ///< the largest one's share of the web area
  int patches = 0;                  ///< connected regions of the other cells
  double mean_web_width = 0;        ///< 2 x web area / border length (a strip's width)
  double median_patch_diameter = 0; ///< 2 sqrt(area / pi) of the median patch by area
};

/// `web` holds one entry per owned cell. Sums through region_moments: the same bits on any number
/// of ranks. Every rank gets the result. Collective.
WebNetwork measure_web(const par::Comm& comm, const geom::SurfaceCells& cells,
                       std::span<const char> web);

} // namespace texsim::pipelines::turk_rd
