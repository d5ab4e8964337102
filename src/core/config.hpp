#pragma once
/// Reading YAML configs into typed structs with errors that name the key path.
///
/// A ConfigDocument owns the YAML tree and remembers every key the schema asked for. Pipelines read
/// their section through ConfigSection::get/require/choice/section; after reading,
/// ConfigDocument::check_unknown_keys() turns any key nobody asked for into an InputError with a
/// "did you mean" hint. Typical use:
///
///   auto time = root.section("fem_rd").section("time");
///   settings.dt = time.get<double>("dt", 0.1, positive());   // "fem_rd.time.dt: expected ..."
#include "core/error.hpp"

#include <yaml-cpp/yaml.h>

#include <array>
#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <set>
#include <string>
#include <utility>
#include <vector>

namespace texsim {

/// A constraint on a value: returns an empty string when the value is acceptable, otherwise what
/// was expected ("a positive number").
template <class T> using Constraint = std::function<std::string(const T&)>;

Constraint<double> positive();
Constraint<double> non_negative();
Constraint<double> in_range(double lo, double hi); ///< closed interval [lo, hi]
Constraint<int> positive_int();
Constraint<int> non_negative_int();
Constraint<int> int_in_range(int lo, int hi);

class ConfigDocument;

/// One mapping of the config (possibly absent: then every get() returns its default).
class ConfigSection {
public:
  /// Optional key with a default; the constraint applies to the given value only.
  template <class T>
  T get(const std::string& key, const T& default_value, const Constraint<T>& check = {}) const;

  /// Key that must be present.
  template <class T> T require(const std::string& key, const Constraint<T>& check = {}) const;

  /// A string key mapped to an enum: choice<Model>("model", Model::kSpots, {{"spots", ...}}).
  template <class E>
  E choice(const std::string& key, E default_value,
           const std::vector<std::pair<std::string, E>>& options) const;

  /// A nested mapping; absent sections read as empty.
  ConfigSection section(const std::string& key) const;

  /// A free-form mapping of scalars (e.g. `petsc:`), returned as strings; its keys are not checked.
  std::map<std::string, std::string> string_map(const std::string& key) const;

  /// True when the key is present in the file (and records it as known).
  bool has(const std::string& key) const;

  /// Names of the keys of this mapping in file order (user-named entries such as species); does not
  /// record them as known: read each one through section()/get() for that.
  std::vector<std::string> keys() const;

  /// "fem_rd.time" (empty for the root).
  const std::string& path() const { return path_; }
  /// "fem_rd.time.dt".
  std::string key_path(const std::string& key) const;

  /// Throws InputError "<path.key>: expected <what>, got <value>".
  [[noreturn]] void fail(const std::string& key, const std::string& expected) const;

private:
  friend class ConfigDocument;
  ConfigSection(ConfigDocument* document, YAML::Node node, std::string path);
  YAML::Node lookup(const std::string& key) const;
  std::string shown_value(const std::string& key) const;

  ConfigDocument* document_;
  YAML::Node node_;
  std::string path_;
};

/// The whole config: parsed YAML plus the set of keys the schema knows.
class ConfigDocument {
public:
  /// Parses YAML text; `source` (file name) is used in messages. Throws InputError on bad YAML.
  /// ${TEXSIM_DATA} in any value (here and in --set values) becomes the environment variable
  /// TEXSIM_DATA, or "data" when it is unset: where an installed texsim finds its data.
  static ConfigDocument parse(const std::string& text, const std::string& source);
  /// Reads and parses a file. Throws InputError if it is missing or unreadable.
  static ConfigDocument load(const std::string& path);

  /// Applies `key.path=value` (value parsed as YAML scalar/flow). Throws InputError on bad syntax.
  void set_override(const std::string& assignment);

  ConfigSection root();

  /// Throws InputError for the first key present in the file that no reader asked for.
  void check_unknown_keys() const;

  /// The document as canonical YAML text (after overrides): what every rank parses.
  std::string emit() const;

  /// Hash of the document without the sections that do not change the discrete problem
  /// (`output`, `checkpoint`, and `petsc`, whose solver options change only how accurately it is
  /// solved) and without `run_length_keys` (key paths such as "fem_rd.time.steps" that only say
  /// when to stop, so a finished run can be continued): checkpoints from a run with another hash
  /// are refused.
  std::string result_hash(const std::vector<std::string>& run_length_keys = {}) const;

  const std::string& source() const { return source_; }

  ConfigDocument(ConfigDocument&&) = default;
  ConfigDocument& operator=(ConfigDocument&&) = default;

private:
  friend class ConfigSection;
  ConfigDocument(YAML::Node root, std::string source);
  void remember(const std::string& path) const { known_->insert(path); }
  void remember_free_form(const std::string& path) const { free_form_->insert(path); }

  YAML::Node root_;
  std::string source_;
  std::shared_ptr<std::set<std::string>> known_;
  std::shared_ptr<std::set<std::string>> free_form_;
};

/// Edit distance, for "did you mean" hints.
std::size_t edit_distance(const std::string& a, const std::string& b);

namespace detail {
/// Converts a scalar node to T or returns nullopt; "what" names T for messages ("a number").
template <class T> std::optional<T> convert(const YAML::Node& node);
template <class T> std::string type_name();
#define TEXSIM_CONFIG_TYPE(T)                                                                      \
  template <> std::optional<T> convert<T>(const YAML::Node& node);                                 \
  template <> std::string type_name<T>();
TEXSIM_CONFIG_TYPE(double)
TEXSIM_CONFIG_TYPE(int)
TEXSIM_CONFIG_TYPE(std::int64_t)
TEXSIM_CONFIG_TYPE(std::uint64_t)
TEXSIM_CONFIG_TYPE(bool)
TEXSIM_CONFIG_TYPE(std::string)
TEXSIM_CONFIG_TYPE(std::vector<double>)
TEXSIM_CONFIG_TYPE(std::vector<std::string>)
using Vec3Array = std::array<double, 3>;
TEXSIM_CONFIG_TYPE(Vec3Array)
#undef TEXSIM_CONFIG_TYPE
/// True for a scalar YAML reads as an infinite or NaN number (.inf, -.Inf, .nan).
bool is_non_finite_number(const YAML::Node& node);
} // namespace detail

template <class T>
T ConfigSection::get(const std::string& key, const T& default_value,
                     const Constraint<T>& check) const {
  if (!has(key))
    return default_value;
  return require<T>(key, check);
}

template <class T>
T ConfigSection::require(const std::string& key, const Constraint<T>& check) const {
  document_->remember(key_path(key));
  YAML::Node node = lookup(key);
  if (!node || node.IsNull())
    fail(key, detail::type_name<T>() + " (required key is missing)");
  const std::optional<T> value = detail::convert<T>(node);
  if (!value)
    fail(key, detail::is_non_finite_number(node) ? "a finite number" : detail::type_name<T>());
  if (check) {
    const std::string expected = check(*value);
    if (!expected.empty())
      fail(key, expected);
  }
  return *value;
}

template <class E>
E ConfigSection::choice(const std::string& key, E default_value,
                        const std::vector<std::pair<std::string, E>>& options) const {
  if (!has(key))
    return default_value;
  const std::string text = require<std::string>(key);
  std::string listed;
  for (const auto& [name, value] : options) {
    if (name == text)
      return value;
    listed += (listed.empty() ? "" : ", ") + name;
  }
  fail(key, "one of " + listed);
}

} // namespace texsim
