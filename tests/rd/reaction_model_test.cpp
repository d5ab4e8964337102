#include "rd/reaction_model.hpp"
#include "support/input_error.hpp"

#include "core/config.hpp"
#include "rd/random_substrate.hpp"
#include "support/test_data.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <numeric>
#include <random>
#include <string>

namespace texsim::rd {
namespace {

constexpr std::uint64_t kSeed = 20240611;

/// Vertices with scattered ids and positions, and a state with different values at each vertex.
struct Fixture {
  std::vector<std::int64_t> ids;
  std::vector<double> xyz;
  std::vector<std::vector<double>> state;

  explicit Fixture(std::size_t n) : state(2) {
    for (std::size_t v = 0; v < n; ++v) {
      ids.push_back(1000 + 7 * static_cast<std::int64_t>(v) + static_cast<std::int64_t>(v * v));
      xyz.insert(xyz.end(), {0.1 * v, 1.0 - 0.05 * v, std::sin(0.3 * v)});
      state[0].push_back(3.0 + 0.37 * std::cos(1.1 * v));
      state[1].push_back(4.5 - 0.29 * std::sin(0.7 * v));
    }
  }
  VertexData vertices() const { return {ids, xyz}; }
  std::vector<std::span<const double>> spans() const { return {state[0], state[1]}; }
};

struct Built {
  ConfigDocument document;
  std::unique_ptr<ReactionModel> model;
};

Built build(const std::string& model_yaml, std::uint64_t seed = kSeed) {
  auto document = ConfigDocument::parse("fem_rd:\n  model: " + model_yaml + "\n", "test.yaml");
  auto model = make_reaction_model(document.root().section("fem_rd").section("model"), seed);
  document.check_unknown_keys();
  return {std::move(document), std::move(model)};
}

std::vector<SpeciesCoefficients> coefficients_of(const ReactionModel& model, const Fixture& f,
                                                 double t = 0.0) {
  std::vector<SpeciesCoefficients> out;
  model.coefficients(t, f.spans(), f.vertices(), out);
  return out;
}

void expect_close(double value, double reference) {
  EXPECT_NEAR(value, reference, 1e-13 * std::max(1.0, std::abs(reference)));
}

TEST(TuringSpots, CoefficientsAreThePapersSplit) {
  const Fixture f(40);
  const auto built = build("{type: turing_spots, s: 0.0375}");
  EXPECT_EQ(built.model->species(), (std::vector<std::string>{"a", "b"}));
  const auto c = coefficients_of(*built.model, f);
  ASSERT_EQ(c.size(), 2u);
  EXPECT_EQ(c[0].diffusion, 0.125);
  EXPECT_EQ(c[1].diffusion, 0.03125);
  const double s = 0.0375;
  const RandomSubstrate beta(kSeed, 12.0, 0.1);
  for (std::size_t v = 0; v < f.ids.size(); ++v) {
    const double a = f.state[0][v];
    const double b = f.state[1][v];
    const double bv = beta.at(f.ids[v]);
    EXPECT_EQ(c[0].linear[v], -s * b);
    EXPECT_EQ(c[0].source[v], 16.0 * s);
    EXPECT_EQ(c[1].linear[v], s * (a - 1.0));
    EXPECT_EQ(c[1].source[v], -s * bv);
    // C2 u + C3 is the full reaction of eqs. (12)-(13).
    expect_close(c[0].linear[v] * a + c[0].source[v], s * (16.0 - a * b));
    expect_close(c[1].linear[v] * b + c[1].source[v], s * (a * b - b - bv));
  }
}

TEST(TuringSpots, HomogeneousSteadyStateAtBeta12) {
  const auto built = build("{type: turing_spots, beta_spread: 0}");
  Fixture f(10);
  const auto initial = built.model->initial_state(f.vertices());
  ASSERT_EQ(initial.size(), 2u);
  for (std::size_t v = 0; v < f.ids.size(); ++v) {
    EXPECT_EQ(initial[0][v], 4.0);
    EXPECT_EQ(initial[1][v], 4.0);
  }
  f.state = initial;
  const auto c = coefficients_of(*built.model, f);
  for (std::size_t v = 0; v < f.ids.size(); ++v) {
    EXPECT_NEAR(c[0].linear[v] * 4.0 + c[0].source[v], 0.0, 1e-15);
    EXPECT_NEAR(c[1].linear[v] * 4.0 + c[1].source[v], 0.0, 1e-15);
  }
}

TEST(Substrate, InRangeUniformAndKeyedBySeedAndId) {
  const RandomSubstrate beta(kSeed, 12.0, 0.1);
  double sum = 0.0;
  int below = 0;
  const int n = 20000;
  for (int id = 0; id < n; ++id) {
    const double value = beta.at(id);
    ASSERT_GE(value, 11.9);
    ASSERT_LT(value, 12.1);
    sum += value;
    below += value < 12.0 ? 1 : 0;
  }
  EXPECT_NEAR(sum / n, 12.0, 0.003); // standard error 0.1 / sqrt(3 n) = 0.0004
  EXPECT_NEAR(below, n / 2, 400);
  EXPECT_EQ(beta.at(12345), RandomSubstrate(kSeed, 12.0, 0.1).at(12345));
  EXPECT_NE(beta.at(12345), RandomSubstrate(kSeed + 1, 12.0, 0.1).at(12345));
  EXPECT_NE(beta.at(12345), beta.at(12346));
}

/// Coefficients of a permuted subset of the vertices equal those of the full set at the same ids:
/// nothing depends on the partition or on the order in which vertices are passed.
void expect_partition_independent(const ReactionModel& model, double t) {
  const Fixture full(60);
  const auto reference = coefficients_of(model, full, t);
  std::vector<std::size_t> pick(full.ids.size());
  std::iota(pick.begin(), pick.end(), 0);
  std::shuffle(pick.begin(), pick.end(), std::mt19937(7));
  pick.resize(23);
  Fixture subset(0);
  for (const std::size_t v : pick) {
    subset.ids.push_back(full.ids[v]);
    subset.xyz.insert(subset.xyz.end(), full.xyz.begin() + 3 * v, full.xyz.begin() + 3 * v + 3);
    subset.state[0].push_back(full.state[0][v]);
    subset.state[1].push_back(full.state[1][v]);
  }
  const auto part = coefficients_of(model, subset, t);
  ASSERT_EQ(part.size(), reference.size());
  for (std::size_t s = 0; s < part.size(); ++s) {
    EXPECT_EQ(part[s].diffusion, reference[s].diffusion);
    for (std::size_t i = 0; i < pick.size(); ++i) {
      EXPECT_EQ(part[s].linear[i], reference[s].linear[pick[i]]);
      EXPECT_EQ(part[s].source[i], reference[s].source[pick[i]]);
    }
  }
  const auto initial_full = model.initial_state(full.vertices());
  const auto initial_part = model.initial_state(subset.vertices());
  for (std::size_t s = 0; s < initial_full.size(); ++s)
    for (std::size_t i = 0; i < pick.size(); ++i)
      EXPECT_EQ(initial_part[s][i], initial_full[s][pick[i]]);
}

TEST(Substrate, ModelsDoNotDependOnVertexOrderOrSubset) {
  for (const char* yaml :
       {"{type: turing_spots}", "{type: fitzhugh_nagumo}", "{type: forced_oscillator}",
        "{type: expression, species: {a: {diffusion: 1, initial: \"noise + x\", "
        "linear: \"noise*a - y\", source: \"b*t + z\"}, b: {diffusion: 2, initial: \"noise\", "
        "source: \"noise*a\"}}}"}) {
    SCOPED_TRACE(yaml);
    const auto built = build(yaml);
    expect_partition_independent(*built.model, 2.5);
  }
}

TEST(Substrate, SeedChangesTheModel) {
  const Fixture f(5);
  const auto one = coefficients_of(*build("{type: turing_spots}", 1).model, f);
  const auto same = coefficients_of(*build("{type: turing_spots}", 1).model, f);
  const auto other = coefficients_of(*build("{type: turing_spots}", 2).model, f);
  EXPECT_EQ(one[1].source, same[1].source);
  EXPECT_NE(one[1].source, other[1].source);
}

TEST(FitzHughNagumo, CoefficientsAndSplit) {
  const Fixture f(40);
  const auto built = build("{type: fitzhugh_nagumo, s: 0.025, s0: -0.1, s1: 1.5, "
                           "beta_spread: 0.2, diffusion_a: 0.2, diffusion_b: 0.05}");
  const auto c = coefficients_of(*built.model, f);
  ASSERT_EQ(c.size(), 2u);
  EXPECT_EQ(c[0].diffusion, 0.2);
  EXPECT_EQ(c[1].diffusion, 0.05);
  const double s = 0.025, s0 = -0.1, s1 = 1.5;
  const RandomSubstrate beta(kSeed, 0.0, 0.2);
  for (std::size_t v = 0; v < f.ids.size(); ++v) {
    const double a = f.state[0][v];
    const double b = f.state[1][v];
    const double bv = beta.at(f.ids[v]);
    ASSERT_GE(bv, -0.2);
    ASSERT_LT(bv, 0.2);
    EXPECT_EQ(c[0].linear[v], -a * a);
    EXPECT_LE(c[0].linear[v], 0.0); // keeps the step matrix positive definite
    EXPECT_EQ(c[0].source[v], a - b);
    EXPECT_EQ(c[1].linear[v], -s * s1);
    EXPECT_EQ(c[1].source[v], s * (a - s0 - bv));
    expect_close(c[0].linear[v] * a + c[0].source[v], a - a * a * a - b);
    expect_close(c[1].linear[v] * b + c[1].source[v], s * (a - s1 * b - s0 - bv));
  }
}

TEST(FitzHughNagumo, StartsAtTheHomogeneousStateOfS0Zero) {
  const auto built = build("{type: fitzhugh_nagumo, beta_spread: 0}");
  Fixture f(8);
  f.state = built.model->initial_state(f.vertices());
  const auto c = coefficients_of(*built.model, f);
  for (std::size_t v = 0; v < f.ids.size(); ++v) {
    EXPECT_EQ(c[0].linear[v] * f.state[0][v] + c[0].source[v], 0.0);
    EXPECT_EQ(c[1].linear[v] * f.state[1][v] + c[1].source[v], 0.0);
  }
}

TEST(ForcedOscillator, CoefficientsAndSplitOfTheForcedBrusselator) {
  const Fixture f(40);
  const auto built = build("{type: forced_oscillator, gamma: 0.3, delta: 5}");
  EXPECT_EQ(built.model->species(), (std::vector<std::string>{"u", "v"}));
  const double t = 3.7;
  const auto c = coefficients_of(*built.model, f, t);
  ASSERT_EQ(c.size(), 2u);
  EXPECT_EQ(c[0].diffusion, 1.0);
  EXPECT_EQ(c[1].diffusion, 5.0);
  const double cc = 0.5, d = 1.5, forcing = 1.0 + 0.3 * std::cos(1.69 * t);
  const RandomSubstrate beta(kSeed, 0.0, 0.1);
  for (std::size_t v = 0; v < f.ids.size(); ++v) {
    const double u = f.state[0][v];
    const double w = f.state[1][v];
    const double bv = beta.at(f.ids[v]);
    EXPECT_EQ(c[0].linear[v], forcing * u * w - (d + 1.0));
    EXPECT_EQ(c[0].source[v], cc + bv);
    EXPECT_EQ(c[1].linear[v], -u * u);
    EXPECT_EQ(c[1].source[v], d * u);
    expect_close(c[0].linear[v] * u + c[0].source[v],
                 cc + bv - (d + 1.0) * u + forcing * u * u * w);
    expect_close(c[1].linear[v] * w + c[1].source[v], d * u - u * u * w);
  }
}

TEST(ForcedOscillator, UnforcedSteadyStateAndStart) {
  const auto built = build("{type: forced_oscillator, gamma: 0}");
  Fixture f(30);
  const auto initial = built.model->initial_state(f.vertices());
  const RandomSubstrate beta(kSeed, 0.0, 0.1);
  for (std::size_t v = 0; v < f.ids.size(); ++v) {
    EXPECT_EQ(initial[0][v], 0.5 + beta.at(f.ids[v]));
    EXPECT_EQ(initial[1][v], 3.0);
  }
  // u = c, v = d / c is a homogeneous steady state of the reconstructed eqs. (16)-(17).
  const auto flat = build("{type: forced_oscillator, gamma: 0, beta_spread: 0}");
  std::fill(f.state[0].begin(), f.state[0].end(), 0.5);
  std::fill(f.state[1].begin(), f.state[1].end(), 3.0);
  const auto c = coefficients_of(*flat.model, f, 1.0);
  for (std::size_t v = 0; v < f.ids.size(); ++v) {
    EXPECT_NEAR(c[0].linear[v] * 0.5 + c[0].source[v], 0.0, 1e-15);
    EXPECT_NEAR(c[1].linear[v] * 3.0 + c[1].source[v], 0.0, 1e-15);
  }
}

TEST(ForcedOscillator, DeltaZeroMeansVDoesNotDiffuse) {
  const Fixture f(3);
  const auto c = coefficients_of(*build("{type: forced_oscillator, delta: 0}").model, f);
  EXPECT_EQ(c[1].diffusion, 0.0);
  EXPECT_EQ(c[0].diffusion, 1.0);
}

TEST(Expression, TuringFormulasMatchTheBuiltInModel) {
  const Fixture f(50);
  const auto builtin = build("{type: turing_spots, beta_spread: 0}");
  const auto user = build(R"yaml({type: expression, constants: {s: 0.05, beta: 12},
      species: {a: {diffusion: 0.125, initial: "4", linear: "-s*b", source: "16*s"},
                b: {diffusion: 0.03125, initial: "4", linear: "s*(a-1)", source: "-s*beta"}}})yaml");
  EXPECT_EQ(user.model->species(), builtin.model->species());
  EXPECT_EQ(user.model->initial_state(f.vertices()), builtin.model->initial_state(f.vertices()));
  const auto expected = coefficients_of(*builtin.model, f, 1.5);
  const auto got = coefficients_of(*user.model, f, 1.5);
  ASSERT_EQ(got.size(), expected.size());
  for (std::size_t s = 0; s < got.size(); ++s) {
    EXPECT_EQ(got[s].diffusion, expected[s].diffusion);
    for (std::size_t v = 0; v < f.ids.size(); ++v) {
      EXPECT_DOUBLE_EQ(got[s].linear[v], expected[s].linear[v]);
      EXPECT_DOUBLE_EQ(got[s].source[v], expected[s].source[v]);
    }
  }
}

TEST(Expression, PositionTimeNoiseAndSpeciesOrder) {
  const Fixture f(30);
  // Species are taken in file order, not alphabetically.
  const auto built = build(R"yaml({type: expression, constants: {k: 2},
      species: {v: {diffusion: 0, initial: "x + 10*y", linear: "k*t - z", source: "noise"},
                u: {diffusion: 1, initial: "noise", linear: "v", source: "u*v + noise"}}})yaml");
  EXPECT_EQ(built.model->species(), (std::vector<std::string>{"v", "u"}));
  const auto initial = built.model->initial_state(f.vertices());
  const double t = 0.75;
  const auto c = coefficients_of(*built.model, f, t);
  EXPECT_EQ(c[0].diffusion, 0.0);
  EXPECT_EQ(c[1].diffusion, 1.0);
  const CounterRng rng(kSeed, kExpressionNoiseStream);
  double differ = 0.0;
  for (std::size_t v = 0; v < f.ids.size(); ++v) {
    const auto id = static_cast<std::uint64_t>(f.ids[v]);
    const double noise_v = rng.uniform(-1.0, 1.0, id, 0, 0);
    const double noise_u = rng.uniform(-1.0, 1.0, id, 0, 1);
    expect_close(initial[0][v], f.xyz[3 * v] + 10.0 * f.xyz[3 * v + 1]);
    EXPECT_EQ(initial[1][v], noise_u);
    expect_close(c[0].linear[v], 2.0 * t - f.xyz[3 * v + 2]);
    EXPECT_EQ(c[0].source[v], noise_v);
    EXPECT_EQ(c[1].linear[v], f.state[0][v]);
    expect_close(c[1].source[v], f.state[1][v] * f.state[0][v] + noise_u);
    EXPECT_GE(noise_v, -1.0);
    EXPECT_LT(noise_v, 1.0);
    differ += std::abs(noise_v - noise_u);
  }
  EXPECT_GT(differ, 1.0); // the species index keys the noise
}

TEST(Expression, ErrorsNameTheKeyPath) {
  const std::string head = "{type: expression, constants: {s: 0.05}, species: {a: {diffusion: "
                           "0.1, initial: \"4\"}, b: {diffusion: 0.1, initial: \"4\", ";
  EXPECT_EQ(test::input_error_message([&] { build(head + "source: \"s*(a*b-\"}}}"); })
                .rfind("fem_rd.model.species.b.source: cannot parse \"s*(a*b-\": Unexpected end of "
                       "expression at position ",
                       0),
            0u)
      << test::input_error_message([&] { build(head + "source: \"s*(a*b-\"}}}"); });
  const std::string unknown =
      test::input_error_message([&] { build(head + "linear: \"q*a\"}}}"); });
  EXPECT_EQ(unknown.rfind("fem_rd.model.species.b.linear: cannot parse \"q*a\": ", 0), 0u)
      << unknown;
  EXPECT_NE(unknown.find("\"q\""), std::string::npos) << unknown;
  // Species values are not defined at t = 0.
  EXPECT_EQ(test::input_error_message([&] {
              build("{type: expression, species: {a: {diffusion: 1, initial: \"a + 1\"}}}");
            }).rfind("fem_rd.model.species.a.initial: cannot parse \"a + 1\"", 0),
            0u);
  EXPECT_EQ(test::input_error_message([&] {
              build("{type: expression, species: {x: {diffusion: 1, initial: \"1\"}}}");
            }).rfind("fem_rd.model.species.x: the name 'x' is already used", 0),
            0u);
  EXPECT_EQ(test::input_error_message([&] {
              build("{type: expression, constants: {s: fast}, species: {a: {diffusion: 1, "
                    "initial: \"1\"}}}");
            }).rfind("fem_rd.model.constants.s: expected a number", 0),
            0u);
  EXPECT_EQ(test::input_error_message([&] {
              build("{type: expression}");
            }).rfind("fem_rd.model.species:", 0),
            0u);
  EXPECT_EQ(test::input_error_message([&] {
              build("{type: expression, species: {a: {diffusion: -1, initial: \"1\"}}}");
            }).rfind("fem_rd.model.species.a.diffusion: expected a number >= 0", 0),
            0u);
}

TEST(Factory, ReadsOnlyTheChosenModelsKeys) {
  EXPECT_NE(
      test::input_error_message([] { build("{type: gray_scott}"); }).find("fem_rd.model.type"),
      std::string::npos);
  // Every key of each model is known to the config layer ...
  EXPECT_NO_THROW(build("{type: turing_spots, s: 0.025, beta: 12, beta_spread: 0.1, "
                        "diffusion_a: 0.125, diffusion_b: 0.03125, initial_a: 4, initial_b: 4}"));
  EXPECT_NO_THROW(build("{type: fitzhugh_nagumo, s: 0.05, s0: 0, s1: 2, beta_spread: 0.1, "
                        "diffusion_a: 0.125, diffusion_b: 0.03125, initial_a: 0, initial_b: 0}"));
  EXPECT_NO_THROW(build("{type: forced_oscillator, c: 0.5, d: 1.5, gamma: 0.1, omega_f: 1.69, "
                        "delta: 0, beta_spread: 0.1}"));
  // ... and another model's key is not.
  EXPECT_NE(test::input_error_message([] {
              build("{type: turing_spots, gamma: 0.1}");
            }).find("unknown key 'fem_rd.model.gamma'"),
            std::string::npos);
  EXPECT_NE(test::input_error_message([] {
              build("{type: turing_spots, s: -1}");
            }).find("fem_rd.model.s:"),
            std::string::npos);
  // The default model is the paper's spot model.
  EXPECT_EQ(build("{}").model->species(), (std::vector<std::string>{"a", "b"}));
}

} // namespace
} // namespace texsim::rd

namespace texsim::rd {
namespace {

/// Rates C2 u + C3 of every species at every vertex for the given state.
std::vector<std::vector<double>> rates(const ReactionModel& model, const VertexData& vertices,
                                       const std::vector<std::vector<double>>& state) {
  std::vector<std::span<const double>> spans(state.begin(), state.end());
  std::vector<SpeciesCoefficients> out;
  model.coefficients(0.0, spans, vertices, out);
  std::vector<std::vector<double>> result(state.size());
  for (std::size_t s = 0; s < state.size(); ++s)
    for (std::size_t v = 0; v < state[s].size(); ++v)
      result[s].push_back(out[s].linear[v] * state[s][v] + out[s].source[v]);
  return result;
}

TEST(MeinhardtStripes, StartsAtTheUniformSteadyState) {
  const auto built = build("{type: meinhardt_stripes, substrate_spread: 0}");
  Fixture f(20);
  const auto initial = built.model->initial_state(f.vertices());
  ASSERT_EQ(initial.size(), 5u);
  EXPECT_DOUBLE_EQ(initial[0][0], 0.75); // beta / (2 alpha)
  EXPECT_DOUBLE_EQ(initial[2][0], 0.140625);
  for (const auto& species : rates(*built.model, f.vertices(), initial))
    for (const double rate : species)
      EXPECT_NEAR(rate, 0.0, 1e-15);
}

TEST(MeinhardtStripes, RatesAreMeinhardtsEquations) {
  const auto built = build("{type: meinhardt_stripes, substrate_spread: 0, rho0: 0.001, "
                           "rho1: 0.002}");
  Fixture f(1);
  const double g1 = 0.9, g2 = 0.4, r = 0.2, s1 = 0.6, s2 = 0.8;
  const auto rate = rates(*built.model, f.vertices(), {{g1}, {g2}, {r}, {s1}, {s2}});
  expect_close(rate[0][0], 0.01 * s2 * g1 * g1 / r - 0.04 * g1 + 0.001);
  expect_close(rate[1][0], 0.01 * s1 * g2 * g2 / r - 0.04 * g2 + 0.001);
  expect_close(rate[2][0], 0.01 * s2 * g1 * g1 + 0.01 * s1 * g2 * g2 - 0.06 * r);
  expect_close(rate[3][0], 0.04 * (g1 - s1) + 0.002);
  expect_close(rate[4][0], 0.04 * (g2 - s2) + 0.002);
  EXPECT_EQ(built.model->species(), (std::vector<std::string>{"g1", "g2", "r", "s1", "s2"}));
}

} // namespace
} // namespace texsim::rd
