#pragma once
/// Turing's two-chemical spot model, eqs. (12)-(15) of Bajaj, Zhang, Xu (after Turk 1991):
///   da/dt = s (16 - a b) + D_a Laplace a,
///   db/dt = s (a b - b - beta) + D_b Laplace b,
/// with beta a random substrate per vertex (12 +/- 0.1). The semi-implicit split is the paper's
/// (eqs. (14)-(15), Fig. 2): a: C2 = -s b^n, C3 = 16 s; b: C2 = s (a^n - 1), C3 = -s beta.
#include "rd/random_substrate.hpp"
#include "rd/reaction_model.hpp"

namespace texsim::rd {

/// Parameters, defaulting to Fig. 3 (c) of the paper (s = 0.025 and 0.0375 give Fig. 3 (a), (b)).
struct TuringSpotsParameters {
  double s = 0.05;              ///< reaction rate
  double beta_mean = 12.0;      ///< centre of the random substrate
  double beta_spread = 0.1;     ///< beta is uniform in beta_mean +/- beta_spread
  double diffusion_a = 0.125;   ///< D_a
  double diffusion_b = 0.03125; ///< D_b
  double initial_a = 4.0;       ///< a at t = 0 (the paper's a = b = 4)
  double initial_b = 4.0;       ///< b at t = 0
};

class TuringSpotsModel final : public ReactionModel {
public:
  /// `seed` keys the substrate beta.
  TuringSpotsModel(const TuringSpotsParameters& parameters, std::uint64_t seed);

  std::vector<std::string> species() const override { return {"a", "b"}; }
  std::vector<std::vector<double>> initial_state(const VertexData& vertices) const override;
  void coefficients(double t, const std::vector<std::span<const double>>& state,
                    const VertexData& vertices,
                    std::vector<SpeciesCoefficients>& out) const override;
  /// C2 and C3 of a and b at one vertex from its a, b and beta: the split coefficients() writes,
  /// for explicit kernels that go one vertex at a time.
  void vertex_coefficients(double a, double b, double beta, double linear[2],
                           double source[2]) const {
    const double s = parameters_.s;
    linear[0] = -s * b;
    source[0] = 16.0 * s;
    linear[1] = s * (a - 1.0);
    source[1] = -s * beta;
  }

  /// Concentrations are clamped at zero, as in Turk 1991.
  double lower_bound(std::size_t) const override { return 0.0; }

  const RandomSubstrate* random_substrate() const override { return &beta_; }
  const TuringSpotsModel* as_turing_spots() const override { return this; }

private:
  TuringSpotsParameters parameters_;
  RandomSubstrate beta_;
};

} // namespace texsim::rd
