#pragma once
/// The input texture I_a of Wei-Levoy and its Gaussian pyramid G_a: an image file (reduced by a
/// power of two, cropped) or a procedural tile (a z = 0 slice of vol's stripes or lattice, or a
/// grid of lines for 4-way symmetric synthesis).
#include "img/image.hpp"
#include "pipelines/surface_synthesis/surface_synthesis_settings.hpp"

#include <cstdint>
#include <string>
#include <vector>

namespace texsim::pipelines::surface_synthesis {

/// The exemplar as given: reduced and cropped, before the pyramid. Throws InputError naming
/// `surface_synthesis.exemplar.<key>` when the file cannot be read or the crop leaves the image.
img::RgbImage load_exemplar(const ExemplarSettings& settings, std::uint64_t seed);

/// G_a: [0] the exemplar, [l + 1] blurred (binomial 5-tap) and decimated; periodic filtering for a
/// toroidal border, clamped for discard. Throws InputError naming surface_synthesis.levels when a
/// toroidal level to be decimated has an odd side, or a level would be smaller than 2 x 2.
std::vector<img::RgbImage> exemplar_pyramid(const img::RgbImage& exemplar, int levels,
                                            ExemplarBorder border);

/// A hex digest of the pyramid's pixels and sizes, stored in checkpoints: a restart with another
/// exemplar is refused.
std::string exemplar_hash(const std::vector<img::RgbImage>& pyramid);

} // namespace texsim::pipelines::surface_synthesis
