#include "pipelines/fem_rd/turing_spots_model.hpp"

namespace texsim::pipelines::fem_rd {

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
  const double s = parameters_.s;
  auto& a = out[0];
  auto& b = out[1];
  a.diffusion = parameters_.diffusion_a;
  b.diffusion = parameters_.diffusion_b;
  for (std::size_t v = 0; v < n; ++v) {
    a.linear[v] = -s * state[1][v];
    a.source[v] = 16.0 * s;
    b.linear[v] = s * (state[0][v] - 1.0);
    b.source[v] = -s * substrate_at(beta_, vertices, v);
  }
}

} // namespace texsim::pipelines::fem_rd
