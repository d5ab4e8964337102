#include "vol/periodic_noise.hpp"
#include "vol/procedural_exemplars.hpp"
#include "vol/tile_sampling.hpp"

#include <algorithm>

namespace texsim::vol {
namespace {

/// Seeds the highlight noise apart from the water noise: CounterRng streams of the same seed are
/// shared by every PeriodicFractalNoise, so a different key is what makes the two independent.
constexpr std::uint64_t kHighlightSeedOffset = 0x5EA3A7E9ULL;

float smoothstep(double edge0, double edge1, double x) {
  const double t = std::clamp((x - edge0) / (edge1 - edge0), 0.0, 1.0);
  return static_cast<float>(t * t * (3.0 - 2.0 * t));
}

} // namespace

RgbGrid noise_exemplar(int n, std::uint64_t seed, const NoiseParams& params) {
  const PeriodicFractalNoise water(seed, params.noise_period, params.octaves);
  const PeriodicFractalNoise glints(seed + kHighlightSeedOffset, params.highlight_period, 3);
  return sample_tile(n, [&](double u, double v, double w) {
    const auto depth = static_cast<float>(std::clamp(0.5 + 0.6 * water.fbm(u, v, w), 0.0, 1.0));
    const img::Rgb body = img::lerp(params.deep, params.shallow, depth);
    const float glint =
        smoothstep(params.highlight_threshold,
                   params.highlight_threshold + params.highlight_softness, glints.fbm(u, v, w));
    return img::lerp(body, params.highlight, glint);
  });
}

} // namespace texsim::vol
