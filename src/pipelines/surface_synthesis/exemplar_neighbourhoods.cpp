#include "pipelines/surface_synthesis/exemplar_neighbourhoods.hpp"

#include "core/error.hpp"
#include "core/log.hpp"

#include <cmath>

namespace texsim::pipelines::surface_synthesis {
namespace {

/// Whether the pixels the piecewise-linear interpolation reads at (x, y) all lie inside `image`.
bool inside(const img::RgbImage& image, double x, double y) {
  const double x0 = std::floor(x), y0 = std::floor(y);
  const double x1 = x0 + (x > x0 ? 1 : 0), y1 = y0 + (y > y0 ? 1 : 0);
  return x0 >= 0 && y0 >= 0 && x1 < image.width() && y1 < image.height();
}

} // namespace

img::Rgb interpolate_pixels(const img::RgbImage& image, double x, double y, bool periodic) {
  const double fx0 = std::floor(x), fy0 = std::floor(y);
  const int x0 = int(fx0), y0 = int(fy0);
  const double fx = x - fx0, fy = y - fy0;
  const auto pixel = [&](int dx, int dy) {
    return periodic ? image.periodic(x0 + dx, y0 + dy) : image.at(x0 + dx, y0 + dy);
  };
  const auto mix = [](const img::Rgb& a, double wa, const img::Rgb& b, double wb, const img::Rgb& c,
                      double wc) {
    img::Rgb out;
    for (int ch = 0; ch < 3; ++ch)
      out[ch] = float(wa * a[ch] + wb * b[ch] + wc * c[ch]);
    return out;
  };
  if (fx == 0 && fy == 0)
    return pixel(0, 0);
  // Below the diagonal (fx >= fy): triangle (0,0), (1,0), (1,1); above: (0,0), (0,1), (1,1).
  if (fx >= fy)
    return mix(pixel(0, 0), 1 - fx, pixel(1, 0), fx - fy, pixel(1, 1), fy);
  return mix(pixel(0, 0), 1 - fy, pixel(0, 1), fy - fx, pixel(1, 1), fx);
}

img::Rgb mean_colour(const img::RgbImage& image) {
  double sum[3] = {0, 0, 0};
  for (const auto& c : image.data())
    for (int ch = 0; ch < 3; ++ch)
      sum[ch] += c[ch];
  const double n = double(image.size());
  return {float(sum[0] / n), float(sum[1] / n), float(sum[2] / n)};
}

ExemplarNeighbourhoods exemplar_neighbourhoods(const std::vector<img::RgbImage>& pyramid, int level,
                                               const NeighbourhoodTemplate& layout, Pass pass,
                                               ExemplarBorder border) {
  const img::RgbImage& image = pyramid[std::size_t(level)];
  const bool periodic = border == ExemplarBorder::toroidal;
  const bool read_current = pass == Pass::refine;
  TEXSIM_VERIFY(layout.coarser.empty() || std::size_t(level) + 1 < pyramid.size(),
                "coarser neighbourhood on the coarsest exemplar level");
  ExemplarNeighbourhoods result;
  result.table.dimension = int(3 * layout.samples(pass));
  const auto accept = [&](int x, int y) {
    if (periodic)
      return true;
    if (read_current)
      for (const auto& o : layout.current)
        if (!inside(image, x + o.x(), y + o.y()))
          return false;
    for (const auto& o : layout.coarser)
      if (!inside(pyramid[std::size_t(level) + 1], 0.5 * x + o.x(), 0.5 * y + o.y()))
        return false;
    return true;
  };
  for (int y = 0; y < image.height(); ++y)
    for (int x = 0; x < image.width(); ++x) {
      if (!accept(x, y))
        continue;
      result.pixels.push_back(y * image.width() + x);
      const auto push = [&](const img::Rgb& c) {
        result.table.values.insert(result.table.values.end(), {c.r, c.g, c.b});
      };
      if (read_current)
        for (const auto& o : layout.current) {
          const int px = x + int(o.x()), py = y + int(o.y());
          push(periodic ? image.periodic(px, py) : image.at(px, py));
        }
      for (const auto& o : layout.coarser)
        push(interpolate_pixels(pyramid[std::size_t(level) + 1], 0.5 * x + o.x(), 0.5 * y + o.y(),
                                periodic));
    }
  if (result.pixels.empty())
    throw InputError(log::cat("surface_synthesis.neighbourhoods: with exemplar.border: discard no ",
                              image.width(), " x ", image.height(), " pixel of exemplar level ",
                              level,
                              " has its whole neighbourhood inside; use smaller "
                              "neighbourhoods, fewer levels or border: toroidal"));
  return result;
}

} // namespace texsim::pipelines::surface_synthesis
