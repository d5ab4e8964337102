#pragma once
/// Reaction-diffusion models in the form of the generalized PDE, eq. (2) of Bajaj, Zhang, Xu:
///   du/dt = C0 div(C1 grad u) + C2 u + C3,
/// advanced by the semi-implicit backward Euler step (M + tau L) u^{n+1} = M u^n + tau F, where
/// C2 (the implicit, linear-in-u part of the reaction) and C3 (the explicit source) are evaluated
/// from the state at step n. For constant C0 the equation is used in its multiplied form
///   (du/dt, v) = -(C0 C1 grad u, grad v) + (C2 u, v) + (C3, v),
/// which also allows C0 = 0 (a species that does not diffuse, e.g. delta = 0 in Fig. 5 (a)).
#include "core/config.hpp"
#include "rd/random_substrate.hpp"

#include <cstdint>
#include <limits>
#include <memory>
#include <span>
#include <string>
#include <vector>

namespace texsim::rd {

class TuringSpotsModel;

/// Per-vertex data a model may use: stable ids (for counter-based random numbers that do not depend
/// on the partition) and positions (for user expressions of x, y, z).
struct VertexData {
  std::span<const std::int64_t> ids; ///< id of each local vertex in the input mesh
  std::span<const double> xyz;       ///< 3 coordinates per local vertex
  /// The model's random substrate at each vertex when the caller precomputed it with
  /// ReactionModel::substrate() (explicit solvers evaluate the same vertices every step); empty:
  /// models draw it from the ids.
  std::span<const double> substrate = {};
  std::size_t size() const { return ids.size(); }
};

/// The coefficients of eq. (2) for one species at every local vertex, written by
/// ReactionModel::coefficients().
struct SpeciesCoefficients {
  double diffusion = 1.0;     ///< C0 * C1 (a constant: the model's diffusion rate)
  std::vector<double> linear; ///< C2 at each vertex (treated implicitly)
  std::vector<double> source; ///< C3 at each vertex (treated explicitly)
};

class ReactionModel {
public:
  virtual ~ReactionModel() = default;

  /// Names of the species, in the order of every per-species array ("a", "b").
  virtual std::vector<std::string> species() const = 0;

  /// Values of every species at t = 0 for the given vertices: result[s][v].
  virtual std::vector<std::vector<double>> initial_state(const VertexData& vertices) const = 0;

  /// C0*C1, C2 and C3 of every species at time t (the start of the step) from the state at that
  /// time, state[s][v]; `out` has one entry per species and is resized as needed. Not collective;
  /// depends only on each vertex's own values (and its id / position), so results do not depend
  /// on the partition.
  virtual void coefficients(double t, const std::vector<std::span<const double>>& state,
                            const VertexData& vertices,
                            std::vector<SpeciesCoefficients>& out) const = 0;

  /// Smallest value species s may take; the solver clamps to it after each step. Concentrations
  /// of Turk's spot system stay non-negative this way (Turk 1991 clamps b at zero): without it
  /// b < 0 turns the a-equation's decay into growth and the run blows up.
  virtual double lower_bound(std::size_t species) const {
    return -std::numeric_limits<double>::infinity();
  }

  /// Whether coefficients() may run on several threads at once (on disjoint vertex blocks).
  virtual bool thread_safe() const { return true; }

  /// The model as Turing's spot system, whose per-vertex reaction explicit kernels inline
  /// (turk_rd's cell solver); null for every other model.
  virtual const TuringSpotsModel* as_turing_spots() const { return nullptr; }

  /// Angular frequency of the model's periodic forcing, 0 for an unforced model: the pipeline
  /// measures which phases of the forcing the pattern locks to (fem_rd's locked_phase).
  virtual double forcing_omega() const { return 0.0; }

  /// The model's per-vertex random substrate (beta), if it has one.
  virtual const RandomSubstrate* random_substrate() const { return nullptr; }

  /// The substrate at every vertex, to pass back in VertexData::substrate; empty for models
  /// without one.
  std::vector<double> substrate(const VertexData& vertices) const;
};

/// Substrate value at vertex k: the precomputed one if present, else drawn from its id.
inline double substrate_at(const RandomSubstrate& substrate, const VertexData& vertices,
                           std::size_t k) {
  return vertices.substrate.empty() ? substrate.at(vertices.ids[k]) : vertices.substrate[k];
}

/// Sizes `out` to `species` entries of `vertices` values each (used by every model's
/// coefficients()).
void resize_coefficients(std::vector<SpeciesCoefficients>& out, std::size_t species,
                         std::size_t vertices);

/// Reads `fem_rd.model` (its `type:` and parameters) and builds the model. `seed` keys the random
/// per-vertex substrate (beta). Throws InputError naming the key for bad values or expressions.
std::unique_ptr<ReactionModel> make_reaction_model(const ConfigSection& model, std::uint64_t seed);

} // namespace texsim::rd
