#include "rd/forced_oscillator_model.hpp"

#include <cmath>

namespace texsim::rd {

ForcedOscillatorModel::ForcedOscillatorModel(const ForcedOscillatorParameters& parameters,
                                             std::uint64_t seed)
    : parameters_(parameters), beta_(seed, 0.0, parameters.beta_spread) {}

std::vector<std::vector<double>>
ForcedOscillatorModel::initial_state(const VertexData& vertices) const {
  std::vector<double> u(vertices.size());
  for (std::size_t v = 0; v < vertices.size(); ++v)
    u[v] = parameters_.c + substrate_at(beta_, vertices, v);
  return {std::move(u), std::vector<double>(vertices.size(), parameters_.d / parameters_.c)};
}

void ForcedOscillatorModel::coefficients(double t,
                                         const std::vector<std::span<const double>>& state,
                                         const VertexData& vertices,
                                         std::vector<SpeciesCoefficients>& out) const {
  const std::size_t n = vertices.size();
  resize_coefficients(out, 2, n);
  const double forcing = 1.0 + parameters_.gamma * std::cos(parameters_.omega_f * t);
  const double d = parameters_.d;
  auto& u = out[0];
  auto& v = out[1];
  u.diffusion = 1.0;
  v.diffusion = parameters_.delta;
  for (std::size_t i = 0; i < n; ++i) {
    const double un = state[0][i];
    const double vn = state[1][i];
    u.linear[i] = forcing * un * vn - (d + 1.0);
    u.source[i] = parameters_.c + substrate_at(beta_, vertices, i);
    v.linear[i] = -un * un;
    v.source[i] = d * un;
  }
}

} // namespace texsim::rd
