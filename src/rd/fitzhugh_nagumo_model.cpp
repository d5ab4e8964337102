#include "rd/fitzhugh_nagumo_model.hpp"

namespace texsim::rd {

FitzHughNagumoModel::FitzHughNagumoModel(const FitzHughNagumoParameters& parameters,
                                         std::uint64_t seed)
    : parameters_(parameters), beta_(seed, 0.0, parameters.beta_spread) {}

std::vector<std::vector<double>>
FitzHughNagumoModel::initial_state(const VertexData& vertices) const {
  return {std::vector<double>(vertices.size(), parameters_.initial_a),
          std::vector<double>(vertices.size(), parameters_.initial_b)};
}

void FitzHughNagumoModel::coefficients(double /*t*/,
                                       const std::vector<std::span<const double>>& state,
                                       const VertexData& vertices,
                                       std::vector<SpeciesCoefficients>& out) const {
  const std::size_t n = vertices.size();
  resize_coefficients(out, 2, n);
  const double s = parameters_.s;
  auto& a = out[0];
  auto& b = out[1];
  a.diffusion = parameters_.diffusion_a;
  b.diffusion = parameters_.diffusion_b;
  for (std::size_t v = 0; v < n; ++v) {
    const double an = state[0][v];
    const double bn = state[1][v];
    a.linear[v] = -an * an;
    a.source[v] = an - bn;
    b.linear[v] = -s * parameters_.s1;
    b.source[v] = s * (an - parameters_.s0 - substrate_at(beta_, vertices, v));
  }
}

} // namespace texsim::rd
