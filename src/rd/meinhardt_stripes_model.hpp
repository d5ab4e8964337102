#pragma once
/// Meinhardt's five-chemical stripe system as Turk 1991 uses it (Meinhardt, "Models of Biological
/// Pattern Formation", 1982): two activators g1, g2 compete through a shared inhibitor r, each
/// activator being stabilised by its own slowly equilibrating substance s1, s2:
///   dg1/dt = c s2 g1^2 / r - alpha g1 + D_g Laplace g1 + rho0
///   dg2/dt = c s1 g2^2 / r - alpha g2 + D_g Laplace g2 + rho0
///   dr/dt  = c s2 g1^2 + c s1 g2^2 - beta r
///   ds1/dt = gamma (g1 - s1) + D_s Laplace s1 + rho1
///   ds2/dt = gamma (g2 - s2) + D_s Laplace s2 + rho1
/// Wherever g1 wins, g2 loses: the pattern is stripes of g1 separated by stripes of g2. The random
/// substrate multiplies the autocatalysis of g1 (1 +/- spread per cell), which starts the
/// instability from the uniform steady state g = beta / (2 alpha), r = 2 c g^3 / beta, s = g.
/// The split into eq. (2)'s linear part (C2, the decay) and source (C3) serves both the FEM
/// solver and the explicit cell solver.
#include "rd/random_substrate.hpp"
#include "rd/reaction_model.hpp"

namespace texsim::rd {

/// Defaults: the constants of Turk's stripe program (alpha 0.04, beta 0.06, gamma 0.04,
/// D_g 0.009, D_s 0.2, c 0.01, substrate 1 +/- 0.005).
struct MeinhardtStripesParameters {
  double c = 0.01;                 ///< autocatalysis rate
  double alpha = 0.04;             ///< activator decay
  double beta = 0.06;              ///< inhibitor decay
  double gamma = 0.04;             ///< equilibration rate of s1, s2
  double rho0 = 0.0;               ///< basic activator production
  double rho1 = 0.0;               ///< basic production of s1, s2
  double diffusion_g = 0.009;      ///< D_g
  double diffusion_s = 0.2;        ///< D_s
  double substrate_spread = 0.005; ///< the substrate is uniform in 1 +/- spread
};

class MeinhardtStripesModel final : public ReactionModel {
public:
  /// `seed` keys the substrate.
  MeinhardtStripesModel(const MeinhardtStripesParameters& parameters, std::uint64_t seed);

  std::vector<std::string> species() const override { return {"g1", "g2", "r", "s1", "s2"}; }
  std::vector<std::vector<double>> initial_state(const VertexData& vertices) const override;
  void coefficients(double t, const std::vector<std::span<const double>>& state,
                    const VertexData& vertices,
                    std::vector<SpeciesCoefficients>& out) const override;
  /// Concentrations stay non-negative (r divides).
  double lower_bound(std::size_t) const override { return 0.0; }

  const RandomSubstrate* random_substrate() const override { return &substrate_; }

private:
  MeinhardtStripesParameters parameters_;
  RandomSubstrate substrate_;
};

} // namespace texsim::rd
