#include "vol/colour_ramp.hpp"
#include "vol/periodic_noise.hpp"
#include "vol/procedural_exemplars.hpp"
#include "vol/tile_sampling.hpp"

#include <cmath>
#include <numbers>

namespace texsim::vol {

RgbGrid wood_exemplar(int n, std::uint64_t seed, const WoodParams& params) {
  const PeriodicFractalNoise noise(seed, params.noise_period, params.octaves);
  return sample_tile(n, [&](double u, double v, double w) {
    // (u, v) - 0.5 lies in [-0.5, 0.5): the offset to the nearest copy of the central axis, so
    // the radius is continuous and periodic across tile faces.
    const double radius = std::hypot(u - 0.5, v - 0.5) + params.ring_noise * noise.fbm(u, v, w);
    const double ring = 0.5 + 0.5 * std::cos(2.0 * std::numbers::pi * params.rings * radius);
    const auto t = static_cast<float>(ring * ring * ring); // thin dark late-wood rings
    return colour_ramp({{0.0f, {0.78f, 0.58f, 0.36f}}, {1.0f, {0.42f, 0.24f, 0.12f}}}, t);
  });
}

} // namespace texsim::vol
