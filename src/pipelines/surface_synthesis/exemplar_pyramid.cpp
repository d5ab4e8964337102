#include "pipelines/surface_synthesis/exemplar_pyramid.hpp"

#include "core/error.hpp"
#include "core/hash.hpp"
#include "core/log.hpp"
#include "img/gaussian_pyramid.hpp"
#include "img/image_io.hpp"
#include "vol/procedural_exemplars.hpp"

#include <cmath>

namespace texsim::pipelines::surface_synthesis {
namespace {

constexpr const char* kKey = "surface_synthesis.exemplar";

img::RgbImage z0_slice(const vol::RgbGrid& grid) {
  img::RgbImage slice(grid.dims().nx, grid.dims().ny);
  for (int y = 0; y < slice.height(); ++y)
    for (int x = 0; x < slice.width(); ++x)
      slice.at(x, y) = grid.at(x, y, 0);
  return slice;
}

/// Dark lines one eighth of a period wide along x and y on a light ground: the same under 90
/// degree rotations, the 4-way symmetric texture of Wei-Levoy's Fig. 7 (bottom row).
img::RgbImage grid_exemplar(int size, int periods) {
  const img::Rgb line{0.15f, 0.12f, 0.1f}, ground{0.9f, 0.85f, 0.7f};
  img::RgbImage image(size, size, ground);
  const double period = double(size) / periods;
  const auto on_line = [&](int i) {
    const double phase = std::fmod(i + 0.5, period) / period;
    return phase < 0.125;
  };
  for (int y = 0; y < size; ++y)
    for (int x = 0; x < size; ++x)
      if (on_line(x) || on_line(y))
        image.at(x, y) = line;
  return image;
}

img::RgbImage procedural(const ExemplarSettings& settings, std::uint64_t seed) {
  switch (settings.procedural) {
  case ProceduralExemplar::stripes:
    return z0_slice(vol::stripe_exemplar(settings.size, {.periods = settings.periods}));
  case ProceduralExemplar::lattice:
    if (settings.size % settings.periods != 0)
      throw InputError(log::cat(kKey, ".size: a multiple of periods (", settings.periods,
                                ") for the lattice exemplar, got ", settings.size));
    return z0_slice(vol::lattice_exemplar(settings.size, settings.size / settings.periods, seed));
  case ProceduralExemplar::grid:
    return grid_exemplar(settings.size, settings.periods);
  case ProceduralExemplar::none:
    break;
  }
  throw Error("procedural exemplar without a kind");
}

} // namespace

img::RgbImage load_exemplar(const ExemplarSettings& settings, std::uint64_t seed) {
  img::RgbImage image = settings.procedural == ProceduralExemplar::none
                            ? img::read_image(settings.image)
                            : procedural(settings, seed);
  if (settings.reduce > 1) {
    const int steps = int(std::lround(std::log2(settings.reduce)));
    if (image.width() % settings.reduce != 0 || image.height() % settings.reduce != 0)
      throw InputError(log::cat(kKey, ".reduce: a factor dividing the image size ", image.width(),
                                " x ", image.height(), ", got ", settings.reduce));
    image = img::gaussian_pyramid(image, steps + 1, img::Border::periodic).back();
  }
  if (settings.crop) {
    const auto [x0, y0, w, h] = *settings.crop;
    if (x0 + w > image.width() || y0 + h > image.height())
      throw InputError(log::cat(kKey, ".crop: a box inside the ", image.width(), " x ",
                                image.height(), " exemplar, got [", x0, ", ", y0, ", ", w, ", ", h,
                                "]"));
    img::RgbImage cropped(w, h);
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x)
        cropped.at(x, y) = image.at(x0 + x, y0 + y);
    image = std::move(cropped);
  }
  return image;
}

std::vector<img::RgbImage> exemplar_pyramid(const img::RgbImage& exemplar, int levels,
                                            ExemplarBorder border) {
  int w = exemplar.width(), h = exemplar.height();
  for (int level = 0; level + 1 < levels; ++level) {
    if (border == ExemplarBorder::toroidal && (w % 2 || h % 2))
      throw InputError(log::cat("surface_synthesis.levels: a toroidal exemplar pyramid of ", levels,
                                " levels needs sides divisible by 2^", levels - 1, ", got ",
                                exemplar.width(), " x ", exemplar.height(),
                                "; crop the exemplar or use fewer levels"));
    w = (w + 1) / 2;
    h = (h + 1) / 2;
  }
  if (w < 2 || h < 2)
    throw InputError(log::cat("surface_synthesis.levels: ", levels, " levels shrink the ",
                              exemplar.width(), " x ", exemplar.height(),
                              " exemplar below 2 x 2; use fewer levels or a larger exemplar"));
  return img::gaussian_pyramid(exemplar, levels,
                               border == ExemplarBorder::toroidal ? img::Border::periodic
                                                                  : img::Border::clamped);
}

std::string exemplar_hash(const std::vector<img::RgbImage>& pyramid) {
  std::string bytes;
  for (const auto& level : pyramid) {
    const int size[2] = {level.width(), level.height()};
    bytes.append(reinterpret_cast<const char*>(size), sizeof size);
    bytes.append(reinterpret_cast<const char*>(level.data().data()),
                 level.data().size() * sizeof(img::Rgb));
  }
  return hex64(fnv1a64(bytes));
}

} // namespace texsim::pipelines::surface_synthesis
