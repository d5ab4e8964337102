#include "vol/procedural_exemplars.hpp"
#include "vol/tile_sampling.hpp"

#include <cmath>
#include <numbers>

namespace texsim::vol {

RgbGrid stripe_exemplar(int n, const StripeParams& params) {
  TEXSIM_VERIFY(params.periods >= 1, "stripe periods must be >= 1, got " << params.periods);
  return sample_tile(n, [&](double, double v, double) {
    const double t = 0.5 + 0.5 * std::cos(2.0 * std::numbers::pi * params.periods * v);
    return img::lerp(params.dark, params.light, static_cast<float>(t));
  });
}

} // namespace texsim::vol
