#pragma once
/// The exemplar of fluid_lapped: its colours, the feature map F_m that steers the erosion
/// (section 5.2; the paper uses height maps), and an optional displacement image carried by the
/// patches like the colour (the lava of Fig. 12).
#include "img/image.hpp"
#include "pipelines/fluid_lapped/fluid_lapped_settings.hpp"

#include <optional>
#include <string>

namespace texsim::pipelines::fluid_lapped {

struct FluidExemplar {
  img::RgbImage colour;
  /// F_m in [0, 1], one per exemplar texel: the feature_map image's luminance, or the colour's
  /// own luminance when none is given (our default, logged: the paper's exemplars come with one).
  img::GreyImage feature;
  bool feature_is_luminance = false;
  std::optional<img::GreyImage> displacement; ///< luminance of the displacement image
  std::string hash;                           ///< of all three, for checkpoints
};

/// Reads the images named in `settings` (PNG, JPEG or GIMP .pat). Throws InputError naming the
/// key and file when one is missing or unreadable, or when the feature map or displacement does
/// not have the exemplar's size.
FluidExemplar load_fluid_exemplar(const ExemplarSettings& settings);

} // namespace texsim::pipelines::fluid_lapped
