#include "pipelines/fluid_lapped/fluid_exemplar.hpp"

#include "core/error.hpp"
#include "core/hash.hpp"
#include "img/gimp_pattern_reader.hpp"
#include "img/image_io.hpp"

#include <algorithm>
#include <cctype>

namespace texsim::pipelines::fluid_lapped {
namespace {

img::RgbImage read_any_image(const std::filesystem::path& path) {
  auto extension = path.extension().string();
  std::transform(extension.begin(), extension.end(), extension.begin(),
                 [](unsigned char c) { return char(std::tolower(c)); });
  return extension == ".pat" ? img::read_gimp_pattern(path).image : img::read_image(path);
}

/// Rec. 709 luminance, clamped into [0, 1].
img::GreyImage luminance(const img::RgbImage& image) {
  img::GreyImage grey(image.width(), image.height());
  for (int y = 0; y < image.height(); ++y)
    for (int x = 0; x < image.width(); ++x) {
      const auto& c = image.at(x, y);
      grey.at(x, y) = std::clamp(0.2126f * c.r + 0.7152f * c.g + 0.0722f * c.b, 0.0f, 1.0f);
    }
  return grey;
}

/// The luminance of the image at `path` (key `key`), which must have the exemplar's size.
img::GreyImage read_matching(const std::filesystem::path& path, const std::string& key,
                             const img::RgbImage& exemplar) {
  const auto image = read_any_image(path);
  if (image.width() != exemplar.width() || image.height() != exemplar.height())
    throw InputError(key + ": " + path.string() + " is " + std::to_string(image.width()) + " x " +
                     std::to_string(image.height()) + " pixels; expected the exemplar's " +
                     std::to_string(exemplar.width()) + " x " + std::to_string(exemplar.height()));
  return luminance(image);
}

template <typename T> void append_bytes(std::string& bytes, std::span<T> values) {
  bytes.append(reinterpret_cast<const char*>(values.data()), values.size_bytes());
}

} // namespace

FluidExemplar load_fluid_exemplar(const ExemplarSettings& settings) {
  FluidExemplar exemplar;
  exemplar.colour = read_any_image(settings.image);
  if (settings.feature_map.empty()) {
    exemplar.feature = luminance(exemplar.colour);
    exemplar.feature_is_luminance = true;
  } else {
    exemplar.feature =
        read_matching(settings.feature_map, "fluid_lapped.exemplar.feature_map", exemplar.colour);
  }
  if (!settings.displacement.empty())
    exemplar.displacement =
        read_matching(settings.displacement, "fluid_lapped.exemplar.displacement", exemplar.colour);
  std::string bytes;
  append_bytes(bytes, exemplar.colour.data());
  append_bytes(bytes, exemplar.feature.data());
  if (exemplar.displacement)
    append_bytes(bytes, exemplar.displacement->data());
  exemplar.hash = hex64(fnv1a64(bytes));
  return exemplar;
}

} // namespace texsim::pipelines::fluid_lapped
