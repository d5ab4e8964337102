#pragma once
/// The neighbourhood of every exemplar pixel at one pyramid level, laid out by the level's
/// NeighbourhoodTemplate: the candidates the search compares a vertex's neighbourhood with
/// (Wei-Levoy Table 3, line 15, BuildImageNeighborhood).
#include "img/image.hpp"
#include "pipelines/surface_synthesis/neighbourhood_search.hpp"
#include "pipelines/surface_synthesis/neighbourhood_template.hpp"

#include <cstdint>
#include <vector>

namespace texsim::pipelines::surface_synthesis {

struct ExemplarNeighbourhoods {
  NeighbourhoodTable table;         ///< one row per candidate pixel, 3 values (RGB) per sample
  std::vector<std::int32_t> pixels; ///< row -> pixel index y * width + x in G_a(level)
};

/// Rows for every pixel of `pyramid[level]` (toroidal border) or for the pixels whose
/// neighbourhood lies inside the image (discard), in increasing pixel order. The current part
/// reads pixels at (x + dx, y + dy); the coarser part reads `pyramid[level + 1]` at
/// (x / 2 + ox, y / 2 + oy), interpolated linearly on the pixel grid split into triangles along
/// the (x, y) -> (x + 1, y + 1) diagonals: the piecewise-linear surface the mesh neighbourhoods
/// read too. Throws InputError naming surface_synthesis.neighbourhoods when discard leaves no
/// candidate.
ExemplarNeighbourhoods exemplar_neighbourhoods(const std::vector<img::RgbImage>& pyramid, int level,
                                               const NeighbourhoodTemplate& layout, Pass pass,
                                               ExemplarBorder border);

/// The value of `image` at a fractional position by that triangle-wise linear interpolation
/// (periodic when `periodic`, else the position must have its support inside).
img::Rgb interpolate_pixels(const img::RgbImage& image, double x, double y, bool periodic);

/// Mean colour of an image: the value of uncovered neighbourhood samples (Wei-Levoy 3.3).
img::Rgb mean_colour(const img::RgbImage& image);

} // namespace texsim::pipelines::surface_synthesis
