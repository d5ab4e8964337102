#pragma once
/// A reaction model whose species and coefficients of eq. (2) are expression strings given by the
/// user, evaluated with muparser. Each species has a diffusion rate (C0 C1, a number) and three
/// expressions: `initial` (the value at t = 0), `linear` (C2, treated implicitly) and `source` (C3,
/// treated explicitly). Expressions may use
///   - the species names (the values at step n; not in `initial`),
///   - x, y, z (the vertex position) and t (the time at the start of the step; 0 in `initial`),
///   - the user's constants,
///   - noise: uniform in [-1, 1) per vertex, from the counter-based generator keyed by the vertex
///   id
///     and the species index, constant in time (a random substrate like the paper's beta).
#include "rd/reaction_model.hpp"

#include <memory>
#include <string>
#include <utility>
#include <vector>

namespace texsim::rd {

struct ExpressionSpecies {
  std::string name;         ///< variable name in expressions
  double diffusion = 0.0;   ///< C0 * C1
  std::string initial;      ///< value at t = 0
  std::string linear = "0"; ///< C2
  std::string source = "0"; ///< C3
};

struct ExpressionModelSpec {
  std::vector<ExpressionSpecies> species;
  std::vector<std::pair<std::string, double>> constants; ///< name, value
  std::string path; ///< config path of the model ("fem_rd.model"), for messages
};

/// Not thread-safe: initial_state() and coefficients() evaluate with one set of parsers and must be
/// called from one thread at a time (the solver calls them serially on each rank).
class ExpressionModel final : public ReactionModel {
public:
  /// Parses every expression; throws InputError naming the key path
  /// ("fem_rd.model.species.b.source: cannot parse "s*(a*b-": Unexpected end ...") for syntax
  /// errors, unknown variables and invalid or clashing names. `seed` keys `noise`.
  ExpressionModel(ExpressionModelSpec spec, std::uint64_t seed);
  ~ExpressionModel() override;

  std::vector<std::string> species() const override;
  std::vector<std::vector<double>> initial_state(const VertexData& vertices) const override;
  void coefficients(double t, const std::vector<std::span<const double>>& state,
                    const VertexData& vertices,
                    std::vector<SpeciesCoefficients>& out) const override;
  /// One set of parsers with bound variables: one caller at a time.
  bool thread_safe() const override { return false; }

private:
  struct Evaluator;
  ExpressionModelSpec spec_;
  std::unique_ptr<Evaluator> evaluator_;
};

} // namespace texsim::rd
