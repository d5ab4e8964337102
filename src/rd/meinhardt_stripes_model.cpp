#include "rd/meinhardt_stripes_model.hpp"

#include <algorithm>

namespace texsim::rd {

MeinhardtStripesModel::MeinhardtStripesModel(const MeinhardtStripesParameters& parameters,
                                             std::uint64_t seed)
    : parameters_(parameters), substrate_(seed, 1.0, parameters.substrate_spread) {}

std::vector<std::vector<double>>
MeinhardtStripesModel::initial_state(const VertexData& vertices) const {
  const auto& p = parameters_;
  const double g = p.beta / (2.0 * p.alpha);
  const double r = 2.0 * p.c * g * g * g / p.beta;
  const std::size_t n = vertices.size();
  return {std::vector<double>(n, g), std::vector<double>(n, g), std::vector<double>(n, r),
          std::vector<double>(n, g), std::vector<double>(n, g)};
}

void MeinhardtStripesModel::coefficients(double /*t*/,
                                         const std::vector<std::span<const double>>& state,
                                         const VertexData& vertices,
                                         std::vector<SpeciesCoefficients>& out) const {
  const auto& p = parameters_;
  const std::size_t n = vertices.size();
  resize_coefficients(out, 5, n);
  out[0].diffusion = out[1].diffusion = p.diffusion_g;
  out[2].diffusion = 0.0;
  out[3].diffusion = out[4].diffusion = p.diffusion_s;
  // r only ever divides; keep it off zero so a clamped cell cannot produce inf.
  constexpr double kTinyInhibitor = 1e-12;
  for (std::size_t v = 0; v < n; ++v) {
    const double g1 = state[0][v], g2 = state[1][v], r = std::max(state[2][v], kTinyInhibitor);
    const double s1 = state[3][v], s2 = state[4][v];
    const double autocatalysis1 = p.c * s2 * g1 * g1 * substrate_at(substrate_, vertices, v);
    const double autocatalysis2 = p.c * s1 * g2 * g2;
    out[0].linear[v] = -p.alpha;
    out[0].source[v] = autocatalysis1 / r + p.rho0;
    out[1].linear[v] = -p.alpha;
    out[1].source[v] = autocatalysis2 / r + p.rho0;
    out[2].linear[v] = -p.beta;
    out[2].source[v] = autocatalysis1 + autocatalysis2;
    out[3].linear[v] = -p.gamma;
    out[3].source[v] = p.gamma * g1 + p.rho1;
    out[4].linear[v] = -p.gamma;
    out[4].source[v] = p.gamma * g2 + p.rho1;
  }
}

} // namespace texsim::rd
