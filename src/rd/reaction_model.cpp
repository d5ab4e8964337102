#include "rd/reaction_model.hpp"

#include "core/error.hpp"
#include "rd/expression_model.hpp"
#include "rd/fitzhugh_nagumo_model.hpp"
#include "rd/forced_oscillator_model.hpp"
#include "rd/meinhardt_stripes_model.hpp"
#include "rd/turing_spots_model.hpp"

namespace texsim::rd {

void resize_coefficients(std::vector<SpeciesCoefficients>& out, std::size_t species,
                         std::size_t vertices) {
  out.resize(species);
  for (auto& coefficients : out) {
    coefficients.linear.resize(vertices);
    coefficients.source.resize(vertices);
  }
}

std::vector<double> ReactionModel::substrate(const VertexData& vertices) const {
  const RandomSubstrate* random = random_substrate();
  if (!random)
    return {};
  std::vector<double> values(vertices.size());
  for (std::size_t v = 0; v < values.size(); ++v)
    values[v] = random->at(vertices.ids[v]);
  return values;
}

namespace {

enum class ModelType {
  kTuringSpots,
  kMeinhardtStripes,
  kFitzHughNagumo,
  kForcedOscillator,
  kExpression
};

std::unique_ptr<ReactionModel> read_turing_spots(const ConfigSection& model, std::uint64_t seed) {
  TuringSpotsParameters p;
  p.s = model.get("s", p.s, non_negative());
  p.beta_mean = model.get("beta", p.beta_mean);
  p.beta_spread = model.get("beta_spread", p.beta_spread, non_negative());
  p.diffusion_a = model.get("diffusion_a", p.diffusion_a, non_negative());
  p.diffusion_b = model.get("diffusion_b", p.diffusion_b, non_negative());
  p.initial_a = model.get("initial_a", p.initial_a);
  p.initial_b = model.get("initial_b", p.initial_b);
  return std::make_unique<TuringSpotsModel>(p, seed);
}

std::unique_ptr<ReactionModel> read_meinhardt_stripes(const ConfigSection& model,
                                                      std::uint64_t seed) {
  MeinhardtStripesParameters p;
  p.c = model.get("c", p.c, positive());
  p.alpha = model.get("alpha", p.alpha, positive());
  p.beta = model.get("beta", p.beta, positive());
  p.gamma = model.get("gamma", p.gamma, non_negative());
  p.rho0 = model.get("rho0", p.rho0, non_negative());
  p.rho1 = model.get("rho1", p.rho1, non_negative());
  p.diffusion_g = model.get("diffusion_g", p.diffusion_g, non_negative());
  p.diffusion_s = model.get("diffusion_s", p.diffusion_s, non_negative());
  p.substrate_spread = model.get("substrate_spread", p.substrate_spread, in_range(0.0, 0.5));
  return std::make_unique<MeinhardtStripesModel>(p, seed);
}

std::unique_ptr<ReactionModel> read_fitzhugh_nagumo(const ConfigSection& model,
                                                    std::uint64_t seed) {
  FitzHughNagumoParameters p;
  p.s = model.get("s", p.s, non_negative());
  p.s0 = model.get("s0", p.s0);
  p.s1 = model.get("s1", p.s1);
  p.beta_spread = model.get("beta_spread", p.beta_spread, non_negative());
  p.diffusion_a = model.get("diffusion_a", p.diffusion_a, non_negative());
  p.diffusion_b = model.get("diffusion_b", p.diffusion_b, non_negative());
  p.initial_a = model.get("initial_a", p.initial_a);
  p.initial_b = model.get("initial_b", p.initial_b);
  return std::make_unique<FitzHughNagumoModel>(p, seed);
}

std::unique_ptr<ReactionModel> read_forced_oscillator(const ConfigSection& model,
                                                      std::uint64_t seed) {
  ForcedOscillatorParameters p;
  p.c = model.get("c", p.c, positive());
  p.d = model.get("d", p.d, non_negative());
  p.gamma = model.get("gamma", p.gamma, non_negative());
  p.omega_f = model.get("omega_f", p.omega_f, non_negative());
  p.delta = model.get("delta", p.delta, non_negative());
  p.beta_spread = model.get("beta_spread", p.beta_spread, non_negative());
  return std::make_unique<ForcedOscillatorModel>(p, seed);
}

std::unique_ptr<ReactionModel> read_expression(const ConfigSection& model, std::uint64_t seed) {
  ExpressionModelSpec spec;
  spec.path = model.path();
  const ConfigSection constants = model.section("constants");
  for (const std::string& name : constants.keys())
    spec.constants.emplace_back(name, constants.require<double>(name));
  if (!model.has("species"))
    model.fail("species", "a mapping of species names to {diffusion, initial, linear, source}");
  const ConfigSection species = model.section("species");
  for (const std::string& name : species.keys()) {
    const ConfigSection entry = species.section(name);
    ExpressionSpecies s;
    s.name = name;
    s.diffusion = entry.require<double>("diffusion", non_negative());
    s.initial = entry.require<std::string>("initial");
    s.linear = entry.get<std::string>("linear", s.linear);
    s.source = entry.get<std::string>("source", s.source);
    spec.species.push_back(std::move(s));
  }
  return std::make_unique<ExpressionModel>(std::move(spec), seed);
}

} // namespace

std::unique_ptr<ReactionModel> make_reaction_model(const ConfigSection& model, std::uint64_t seed) {
  const auto type = model.choice<ModelType>("type", ModelType::kTuringSpots,
                                            {{"turing_spots", ModelType::kTuringSpots},
                                             {"meinhardt_stripes", ModelType::kMeinhardtStripes},
                                             {"fitzhugh_nagumo", ModelType::kFitzHughNagumo},
                                             {"forced_oscillator", ModelType::kForcedOscillator},
                                             {"expression", ModelType::kExpression}});
  switch (type) {
  case ModelType::kTuringSpots:
    return read_turing_spots(model, seed);
  case ModelType::kMeinhardtStripes:
    return read_meinhardt_stripes(model, seed);
  case ModelType::kFitzHughNagumo:
    return read_fitzhugh_nagumo(model, seed);
  case ModelType::kForcedOscillator:
    return read_forced_oscillator(model, seed);
  case ModelType::kExpression:
    return read_expression(model, seed);
  }
  throw Error("unhandled reaction model type");
}

} // namespace texsim::rd
