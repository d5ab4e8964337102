#include "core/rng.hpp"
#include "vol/periodic_noise.hpp"
#include "vol/procedural_exemplars.hpp"
#include "vol/tile_sampling.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <vector>

namespace texsim::vol {
namespace {

constexpr std::uint32_t kStrokeLayerStream = 0x7605; // CounterRng stream of per-slab patterns

/// Stroke directions with integer components, so the phase strokes * (a u + b v) changes by an
/// integer across the tile and the pattern tiles along x and y.
constexpr std::array<std::array<int, 2>, 4> kDirections{{{1, 0}, {0, 1}, {1, 1}, {1, -1}}};

struct Slab {
  std::array<int, 2> direction;
  double phase; ///< periods
};

/// Strength in [0, 1] of a stroke centred at `centre` (fraction of a period) at fraction `s`:
/// a triangle `width` wide on each side.
double stroke_strength(double s, double centre, double width) {
  const double d = std::abs(s - centre - std::floor(s - centre + 0.5));
  return std::max(0.0, 1.0 - d / width);
}

} // namespace

RgbGrid stroke_exemplar(int n, std::uint64_t seed, const StrokeParams& params) {
  TEXSIM_VERIFY(params.layers >= 1 && params.strokes >= 1 && params.width > 0.0 &&
                    params.width < 0.25,
                "strokes need layers >= 1, strokes >= 1 and width in (0, 0.25), got "
                    << params.layers << ", " << params.strokes << ", " << params.width);
  const CounterRng rng(seed, kStrokeLayerStream);
  std::vector<Slab> slabs;
  for (int layer = 0; layer < params.layers; ++layer) {
    const auto id = static_cast<std::uint64_t>(layer);
    const auto pick = static_cast<std::size_t>(rng.uniform(id, 0, 0) * kDirections.size());
    slabs.push_back({kDirections[std::min(pick, kDirections.size() - 1)], rng.uniform(id, 0, 1)});
  }
  const PeriodicFractalNoise warp(seed, params.noise_period, 3);
  return sample_tile(n, [&](double u, double v, double w) {
    const int layer = std::min(static_cast<int>(std::floor(w * params.layers)), params.layers - 1);
    const Slab& slab = slabs[static_cast<std::size_t>(layer)];
    // The warp noise is read at the slab's centre depth: constant along z inside a slab.
    const double depth = (layer + 0.5) / params.layers;
    const double phase = params.strokes * (slab.direction[0] * u + slab.direction[1] * v) +
                         slab.phase + params.warp * warp.fbm(u, v, depth);
    const double s = phase - std::floor(phase);
    const auto black = static_cast<float>(stroke_strength(s, 0.25, params.width));
    const auto white = static_cast<float>(stroke_strength(s, 0.75, params.width));
    return img::lerp(img::lerp(params.background, img::Rgb::grey(0.0f), black),
                     img::Rgb::grey(1.0f), white);
  });
}

} // namespace texsim::vol
