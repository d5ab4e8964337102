#pragma once
/// The FitzHugh-Nagumo variant of Fig. 4 of Bajaj, Zhang, Xu:
///   da/dt = a - a^3 - b + D_a Laplace a,
///   db/dt = s (a - s1 b - s0 - beta') + D_b Laplace b.
/// This is the bistable FitzHugh-Nagumo form used by Hagberg and Meron and by Lin et al. (2000),
/// u_t = u - u^3 - v + Laplace u, v_t = eps (u - a1 v - a0) + delta Laplace v, with s = eps,
/// s1 = a1, s0 = a0. The paper gives no s0, s1: the defaults s1 = 2, s0 = 0 make the kinetics
/// bistable (a = +/-1/sqrt(2) are stable, a = 0 is not) and, with the paper's D_a, D_b and s =
/// 0.025 ... 0.05, the random substrate grows into domains of both phases that persist (a 2D
/// finite-difference run to t = 1000: std(a) ~ 0.8, half the area in each phase). With
/// D_b < D_a there is no Turing instability here: the fronts between the phases keep moving (the
/// Bloch regime of Hagberg and Meron), so the pattern is a snapshot, not a stationary state.
/// s0 != 0 favours one phase: s0 = -0.05 ends in a uniform state in the same run.
///
/// The random substrate (the paper's "beta = 12 +/- 0.1") enters as beta' = beta - 12, uniform in
/// +/- beta_spread per vertex, a local shift of s0, the way beta shifts the source of G in Turing's
/// model; the start is the homogeneous state a = b = 0 of s0 = 0.
///
/// Split: a: C2 = -(a^n)^2, C3 = a^n - b^n (the growth term a is explicit so that C2 <= 0 and the
/// step matrix M + tau (L - C2 M) stays symmetric positive definite for every time step);
/// b: C2 = -s s1, C3 = s (a^n - s0 - beta').
#include "rd/random_substrate.hpp"
#include "rd/reaction_model.hpp"

namespace texsim::rd {

struct FitzHughNagumoParameters {
  double s = 0.05;              ///< time-scale ratio of the inhibitor b (Fig. 4: 0.025 ... 0.05)
  double s0 = 0.0;              ///< offset of the b nullcline
  double s1 = 2.0;              ///< slope factor of the b nullcline
  double beta_spread = 0.1;     ///< beta' is uniform in +/- beta_spread
  double diffusion_a = 0.125;   ///< D_a
  double diffusion_b = 0.03125; ///< D_b
  double initial_a = 0.0;       ///< a at t = 0
  double initial_b = 0.0;       ///< b at t = 0
};

class FitzHughNagumoModel final : public ReactionModel {
public:
  /// `seed` keys the substrate beta'.
  FitzHughNagumoModel(const FitzHughNagumoParameters& parameters, std::uint64_t seed);

  std::vector<std::string> species() const override { return {"a", "b"}; }
  std::vector<std::vector<double>> initial_state(const VertexData& vertices) const override;
  void coefficients(double t, const std::vector<std::span<const double>>& state,
                    const VertexData& vertices,
                    std::vector<SpeciesCoefficients>& out) const override;

  const RandomSubstrate* random_substrate() const override { return &beta_; }

private:
  FitzHughNagumoParameters parameters_;
  RandomSubstrate beta_;
};

} // namespace texsim::rd
