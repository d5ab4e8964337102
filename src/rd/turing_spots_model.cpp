#include "rd/turing_spots_model.hpp"

namespace texsim::rd {

TuringSpotsModel::TuringSpotsModel(const TuringSpotsParameters& parameters, std::uint64_t seed)
    : parameters_(parameters), beta_(seed, parameters.beta_mean, parameters.beta_spread) {}

std::vector<std::vector<double>> TuringSpotsModel::initial_state(const VertexData& vertices) const {
  return {std::vector<double>(vertices.size(), parameters_.initial_a),
          std::vector<double>(vertices.size(), parameters_.initial_b)};
}

void TuringSpotsModel::coefficients(double /*t*/, const std::vector<std::span<const double>>& state,
                                    const VertexData& vertices,
                                    std::vector<SpeciesCoefficients>& out) const {
  const std::size_t n = vertices.size();
  resize_coefficients(out, 2, n);
  auto& a = out[0];
  auto& b = out[1];
  a.diffusion = parameters_.diffusion_a;
  b.diffusion = parameters_.diffusion_b;
  for (std::size_t v = 0; v < n; ++v) {
    double linear[2], source[2];
    vertex_coefficients(state[0][v], state[1][v], substrate_at(beta_, vertices, v), linear, source);
    a.linear[v] = linear[0];
    a.source[v] = source[0];
    b.linear[v] = linear[1];
    b.source[v] = source[1];
  }
}

} // namespace texsim::rd
