#include "rd/expression_model.hpp"

#include "core/error.hpp"
#include "core/rng.hpp"
#include "rd/random_substrate.hpp"

#include <muParser.h>

#include <algorithm>
#include <cctype>
#include <set>

namespace texsim::rd {

namespace {

const std::vector<std::string> kBuiltinNames = {"x", "y", "z", "t", "noise"};

enum class Kind { kInitial, kLinear, kSource };

const char* key_of(Kind kind) {
  switch (kind) {
  case Kind::kInitial:
    return "initial";
  case Kind::kLinear:
    return "linear";
  case Kind::kSource:
    return "source";
  }
  return "";
}

} // namespace

/// The parsers (three per species) and the per-vertex arrays their variables point to. muparser's
/// bulk mode evaluates an expression for all vertices in one call, reading variable k of vertex v
/// at pointer + v.
struct ExpressionModel::Evaluator {
  struct Term {
    mu::Parser parser;
    std::size_t species = 0;
    Kind kind = Kind::kInitial;
  };

  std::vector<std::vector<double>> values; ///< [species][vertex] at step n
  std::vector<std::vector<double>> noise;  ///< [species][vertex]
  std::vector<double> x, y, z, t;
  std::vector<Term> terms; ///< initial, linear, source of species 0, then of species 1 ...
  std::size_t bound_size = 0;
  CounterRng rng;

  Evaluator(const ExpressionModelSpec& spec, std::uint64_t seed)
      : values(spec.species.size()), noise(spec.species.size()), terms(3 * spec.species.size()),
        rng(seed, kExpressionNoiseStream) {
    for (std::size_t s = 0; s < spec.species.size(); ++s) {
      for (const Kind kind : {Kind::kInitial, Kind::kLinear, Kind::kSource}) {
        Term& term = terms[3 * s + static_cast<std::size_t>(kind)];
        term.species = s;
        term.kind = kind;
        for (const auto& [name, value] : spec.constants)
          term.parser.DefineConst(name, value);
      }
    }
    resize(1, spec);
    for (std::size_t s = 0; s < spec.species.size(); ++s) {
      const ExpressionSpecies& species = spec.species[s];
      for (const Kind kind : {Kind::kInitial, Kind::kLinear, Kind::kSource}) {
        Term& term = terms[3 * s + static_cast<std::size_t>(kind)];
        const std::string& text = kind == Kind::kInitial  ? species.initial
                                  : kind == Kind::kLinear ? species.linear
                                                          : species.source;
        try {
          term.parser.SetExpr(text);
          term.parser.Eval();
        } catch (const mu::Parser::exception_type& error) {
          throw InputError(spec.path + ".species." + species.name + "." + key_of(kind) +
                           ": cannot parse \"" + text + "\": " + error.GetMsg());
        }
      }
    }
  }

  /// Sizes every array to n vertices and points the parsers' variables at them.
  void resize(std::size_t n, const ExpressionModelSpec& spec) {
    if (n == bound_size)
      return;
    for (auto& array : values)
      array.resize(n);
    for (auto& array : noise)
      array.resize(n);
    x.resize(n);
    y.resize(n);
    z.resize(n);
    t.resize(n);
    for (Term& term : terms) {
      term.parser.DefineVar("x", x.data());
      term.parser.DefineVar("y", y.data());
      term.parser.DefineVar("z", z.data());
      term.parser.DefineVar("t", t.data());
      term.parser.DefineVar("noise", noise[term.species].data());
      if (term.kind != Kind::kInitial)
        for (std::size_t s = 0; s < values.size(); ++s)
          term.parser.DefineVar(spec.species[s].name, values[s].data());
    }
    bound_size = n;
  }

  /// Fills positions, time and noise of the given vertices.
  void load(const VertexData& vertices, double time, const ExpressionModelSpec& spec) {
    const std::size_t n = vertices.size();
    resize(n, spec);
    for (std::size_t v = 0; v < n; ++v) {
      x[v] = vertices.xyz[3 * v];
      y[v] = vertices.xyz[3 * v + 1];
      z[v] = vertices.xyz[3 * v + 2];
      t[v] = time;
      const auto id = static_cast<std::uint64_t>(vertices.ids[v]);
      for (std::size_t s = 0; s < noise.size(); ++s)
        noise[s][v] = rng.uniform(-1.0, 1.0, id, 0, static_cast<std::uint32_t>(s));
    }
  }

  void evaluate(std::size_t species, Kind kind, std::vector<double>& result) {
    result.resize(bound_size);
    if (bound_size > 0)
      terms[3 * species + static_cast<std::size_t>(kind)].parser.Eval(result.data(),
                                                                      static_cast<int>(bound_size));
  }
};

namespace {

/// Throws InputError unless `name` is a usable, unique variable name.
void check_name(const std::string& name, const std::string& key_path, std::set<std::string>& used) {
  const bool valid = !name.empty() && (std::isalpha(static_cast<unsigned char>(name[0])) != 0) &&
                     name.find_first_not_of("abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ"
                                            "0123456789_") == std::string::npos;
  if (!valid)
    throw InputError(key_path + ": '" + name +
                     "' is not a valid variable name (letters, digits and _, starting with a "
                     "letter)");
  if (!used.insert(name).second)
    throw InputError(key_path + ": the name '" + name +
                     "' is already used (x, y, z, t, noise, species and constants must differ)");
}

} // namespace

ExpressionModel::ExpressionModel(ExpressionModelSpec spec, std::uint64_t seed)
    : spec_(std::move(spec)) {
  if (spec_.species.empty())
    throw InputError(spec_.path + ".species: expected at least one species, got none");
  std::set<std::string> used(kBuiltinNames.begin(), kBuiltinNames.end());
  for (const auto& species : spec_.species)
    check_name(species.name, spec_.path + ".species." + species.name, used);
  for (const auto& [name, value] : spec_.constants)
    check_name(name, spec_.path + ".constants." + name, used);
  try {
    evaluator_ = std::make_unique<Evaluator>(spec_, seed);
  } catch (const mu::Parser::exception_type& error) {
    // A name muparser refuses although it passed check_name (e.g. one of its function names).
    throw InputError(spec_.path + ": the variable name \"" + error.GetToken() +
                     "\" cannot be used: " + error.GetMsg());
  }
}

ExpressionModel::~ExpressionModel() = default;

std::vector<std::string> ExpressionModel::species() const {
  std::vector<std::string> names;
  for (const auto& species : spec_.species)
    names.push_back(species.name);
  return names;
}

std::vector<std::vector<double>> ExpressionModel::initial_state(const VertexData& vertices) const {
  evaluator_->load(vertices, 0.0, spec_);
  std::vector<std::vector<double>> result(spec_.species.size());
  for (std::size_t s = 0; s < result.size(); ++s)
    evaluator_->evaluate(s, Kind::kInitial, result[s]);
  return result;
}

void ExpressionModel::coefficients(double t, const std::vector<std::span<const double>>& state,
                                   const VertexData& vertices,
                                   std::vector<SpeciesCoefficients>& out) const {
  const std::size_t n = vertices.size();
  TEXSIM_VERIFY(state.size() == spec_.species.size(),
                "state has " << state.size() << " species, the model " << spec_.species.size());
  evaluator_->load(vertices, t, spec_);
  for (std::size_t s = 0; s < state.size(); ++s)
    std::copy(state[s].begin(), state[s].begin() + static_cast<std::ptrdiff_t>(n),
              evaluator_->values[s].begin());
  resize_coefficients(out, spec_.species.size(), n);
  for (std::size_t s = 0; s < spec_.species.size(); ++s) {
    out[s].diffusion = spec_.species[s].diffusion;
    evaluator_->evaluate(s, Kind::kLinear, out[s].linear);
    evaluator_->evaluate(s, Kind::kSource, out[s].source);
  }
}

} // namespace texsim::rd
