#include "vol/colour_ramp.hpp"
#include "vol/periodic_noise.hpp"
#include "vol/procedural_exemplars.hpp"
#include "vol/tile_sampling.hpp"

#include <cmath>
#include <numbers>

namespace texsim::vol {

RgbGrid marble_exemplar(int n, std::uint64_t seed, const MarbleParams& params) {
  const PeriodicFractalNoise noise(seed, params.noise_period, params.octaves);
  return sample_tile(n, [&](double u, double v, double w) {
    const double phase = params.stripes * (u + w) + params.turbulence * noise.turbulence(u, v, w);
    const auto t = static_cast<float>(0.5 + 0.5 * std::sin(2.0 * std::numbers::pi * phase));
    return colour_ramp({{0.0f, {0.25f, 0.23f, 0.22f}},
                        {0.3f, {0.62f, 0.6f, 0.57f}},
                        {1.0f, {0.94f, 0.93f, 0.89f}}},
                       t);
  });
}

} // namespace texsim::vol
