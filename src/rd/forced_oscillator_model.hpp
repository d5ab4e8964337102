#pragma once
/// The periodically forced oscillator of Fig. 5 of Bajaj, Zhang, Xu, eqs. (16)-(17), which the
/// paper takes from Lin et al., "Four-phase patterns in forced oscillatory systems", Phys. Rev. E
/// 62, 3790 (2000): the forced Brusselator
///   du/dt = c + beta - (d + 1) u + (1 + Gamma cos(omega_f t)) u^2 v + Laplace u,
///   dv/dt = d u - u^2 v + delta Laplace v.
/// Reconstruction: the paper's eq. (16) reads "- d u"; with it the sum of (16) and (17) is
/// c + beta > 0 at every homogeneous state, so u + v grows without bound. The Brusselator's
/// -(b + 1) u term (b = d here) restores the steady state u = c, v = d / c of Lin et al.'s model.
/// beta is a random substrate per vertex, uniform in +/- beta_spread (the paper's "beta = +/-0.1").
/// Gamma is not given by the paper. Measured with fem_rd's locked_phase (drift of the phase at
/// omega_f / 4 per response period, t = 500) for c = 0.5, d = 1.5, omega_f = 1.69: the homogeneous
/// oscillation (beta_spread 0) locks 1:4 to the forcing (the four-phase regime Lin et al. study)
/// for 0.28 <= Gamma <= 0.4 and drifts for 0.1 (-63 deg), 0.2 (-67), 0.25 (-35), 0.45 (44) and 0.5
/// (94); on Fig. 5's sphere with the substrate it locks at 0.3 for delta = 0, 1 and 5. The default
/// 0.2 is Fig. 5's config (whose textures look like the paper's), outside the tongue.
///
/// Split as in Fig. 2: u: C0 = 1, C2 = (1 + Gamma cos(omega_f t)) u^n v^n - (d + 1),
/// C3 = c + beta; v: C0 = delta (0 is allowed: v does not diffuse), C2 = -(u^n)^2, C3 = d u^n.
/// Start: u = c + beta, v = d / c (the unforced steady state, displaced by the substrate).
#include "rd/random_substrate.hpp"
#include "rd/reaction_model.hpp"

namespace texsim::rd {

/// Parameters, defaulting to Fig. 5 (b) of the paper (delta = 0 and 5 give Fig. 5 (a), (c)).
struct ForcedOscillatorParameters {
  double c = 0.5;           ///< feed rate (Brusselator a)
  double d = 1.5;           ///< Brusselator b (oscillates for d > 1 + c^2)
  double gamma = 0.2;       ///< forcing amplitude Gamma
  double omega_f = 1.69;    ///< forcing angular frequency (1/time)
  double delta = 1.0;       ///< diffusion rate of v relative to u
  double beta_spread = 0.1; ///< beta is uniform in +/- beta_spread
};

class ForcedOscillatorModel final : public ReactionModel {
public:
  /// `seed` keys the substrate beta.
  ForcedOscillatorModel(const ForcedOscillatorParameters& parameters, std::uint64_t seed);

  std::vector<std::string> species() const override { return {"u", "v"}; }
  std::vector<std::vector<double>> initial_state(const VertexData& vertices) const override;
  void coefficients(double t, const std::vector<std::span<const double>>& state,
                    const VertexData& vertices,
                    std::vector<SpeciesCoefficients>& out) const override;

  const RandomSubstrate* random_substrate() const override { return &beta_; }
  double forcing_omega() const override { return parameters_.omega_f; }

private:
  ForcedOscillatorParameters parameters_;
  RandomSubstrate beta_;
};

} // namespace texsim::rd
