#include "core/config.hpp"

#include "core/hash.hpp"
#include "core/input_file.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <sstream>

namespace texsim {

Constraint<double> positive() {
  return [](const double& v) { return v > 0 ? "" : std::string("a positive number"); };
}
Constraint<double> non_negative() {
  return [](const double& v) { return v >= 0 ? "" : std::string("a number >= 0"); };
}
Constraint<double> in_range(double lo, double hi) {
  return [lo, hi](const double& v) {
    std::ostringstream out;
    if (!(v >= lo && v <= hi))
      out << "a number in [" << lo << ", " << hi << "]";
    return out.str();
  };
}
Constraint<int> positive_int() {
  return [](const int& v) { return v > 0 ? "" : std::string("a positive integer"); };
}
Constraint<int> non_negative_int() {
  return [](const int& v) { return v >= 0 ? "" : std::string("an integer >= 0"); };
}
Constraint<int> int_in_range(int lo, int hi) {
  return [lo, hi](const int& v) {
    return v >= lo && v <= hi
               ? std::string()
               : "an integer in [" + std::to_string(lo) + ", " + std::to_string(hi) + "]";
  };
}

std::size_t edit_distance(const std::string& a, const std::string& b) {
  std::vector<std::size_t> row(b.size() + 1);
  for (std::size_t j = 0; j <= b.size(); ++j)
    row[j] = j;
  for (std::size_t i = 1; i <= a.size(); ++i) {
    std::size_t diagonal = row[0];
    row[0] = i;
    for (std::size_t j = 1; j <= b.size(); ++j) {
      const std::size_t above = row[j];
      row[j] = std::min({row[j] + 1, row[j - 1] + 1, diagonal + (a[i - 1] != b[j - 1])});
      diagonal = above;
    }
  }
  return row[b.size()];
}

namespace detail {
namespace {
template <class T> std::optional<T> decode(const YAML::Node& node) {
  T value{};
  if (!node.IsScalar() || !YAML::convert<T>::decode(node, value))
    return std::nullopt;
  return value;
}
} // namespace

bool is_non_finite_number(const YAML::Node& node) {
  const auto value = decode<double>(node);
  return value && !std::isfinite(*value);
}

template <> std::optional<double> convert<double>(const YAML::Node& node) {
  // .inf and .nan are YAML numbers, but no texsim setting means them: dt: .inf would run away.
  const auto value = decode<double>(node);
  if (value && !std::isfinite(*value))
    return std::nullopt;
  return value;
}
template <> std::optional<int> convert<int>(const YAML::Node& node) {
  return decode<int>(node);
}
template <> std::optional<std::int64_t> convert<std::int64_t>(const YAML::Node& node) {
  return decode<std::int64_t>(node);
}
template <> std::optional<std::uint64_t> convert<std::uint64_t>(const YAML::Node& node) {
  if (node.IsScalar() && !node.Scalar().empty() && node.Scalar()[0] == '-')
    return std::nullopt;
  return decode<std::uint64_t>(node);
}
template <> std::optional<bool> convert<bool>(const YAML::Node& node) {
  return decode<bool>(node);
}
template <> std::optional<std::string> convert<std::string>(const YAML::Node& node) {
  if (!node.IsScalar())
    return std::nullopt;
  return node.Scalar();
}
template <class T> std::optional<std::vector<T>> decode_sequence(const YAML::Node& node) {
  if (!node.IsSequence())
    return std::nullopt;
  std::vector<T> values;
  for (const auto& item : node) {
    const auto value = convert<T>(item);
    if (!value)
      return std::nullopt;
    values.push_back(*value);
  }
  return values;
}
template <>
std::optional<std::vector<double>> convert<std::vector<double>>(const YAML::Node& node) {
  return decode_sequence<double>(node);
}
template <>
std::optional<std::vector<std::string>> convert<std::vector<std::string>>(const YAML::Node& node) {
  return decode_sequence<std::string>(node);
}
template <>
std::optional<std::array<double, 3>> convert<std::array<double, 3>>(const YAML::Node& node) {
  const auto values = convert<std::vector<double>>(node);
  if (!values || values->size() != 3)
    return std::nullopt;
  return std::array<double, 3>{(*values)[0], (*values)[1], (*values)[2]};
}

template <> std::string type_name<double>() {
  return "a number";
}
template <> std::string type_name<int>() {
  return "an integer";
}
template <> std::string type_name<std::int64_t>() {
  return "an integer";
}
template <> std::string type_name<std::uint64_t>() {
  return "a non-negative integer";
}
template <> std::string type_name<bool>() {
  return "true or false";
}
template <> std::string type_name<std::string>() {
  return "a string";
}
template <> std::string type_name<std::vector<double>>() {
  return "a list of numbers";
}
template <> std::string type_name<std::vector<std::string>>() {
  return "a list of strings";
}
template <> std::string type_name<std::array<double, 3>>() {
  return "a list of 3 numbers";
}
} // namespace detail

ConfigSection::ConfigSection(ConfigDocument* document, YAML::Node node, std::string path)
    : document_(document), node_(std::move(node)), path_(std::move(path)) {}

std::string ConfigSection::key_path(const std::string& key) const {
  return path_.empty() ? key : path_ + "." + key;
}

YAML::Node ConfigSection::lookup(const std::string& key) const {
  if (!node_ || !node_.IsMap())
    return YAML::Node();
  const YAML::Node& map = node_;
  return map[key];
}

bool ConfigSection::has(const std::string& key) const {
  document_->remember(key_path(key));
  const YAML::Node node = lookup(key);
  return node && !node.IsNull();
}

std::vector<std::string> ConfigSection::keys() const {
  std::vector<std::string> names;
  if (!node_ || !node_.IsMap())
    return names;
  for (const auto& item : node_)
    names.push_back(item.first.as<std::string>());
  return names;
}

std::string ConfigSection::shown_value(const std::string& key) const {
  const YAML::Node node = lookup(key);
  if (!node || node.IsNull())
    return "nothing";
  if (node.IsScalar())
    return node.Scalar().empty() ? "an empty string" : shortened(node.Scalar());
  YAML::Emitter out;
  out << YAML::Flow << node;
  return shortened(out.c_str());
}

void ConfigSection::fail(const std::string& key, const std::string& expected) const {
  throw InputError(key_path(key) + ": expected " + expected + ", got " + shown_value(key));
}

ConfigSection ConfigSection::section(const std::string& key) const {
  document_->remember(key_path(key));
  const YAML::Node node = lookup(key);
  if (node && !node.IsNull() && !node.IsMap())
    fail(key, "a mapping of keys");
  return ConfigSection(document_, node && node.IsMap() ? node : YAML::Node(), key_path(key));
}

std::map<std::string, std::string> ConfigSection::string_map(const std::string& key) const {
  document_->remember(key_path(key));
  document_->remember_free_form(key_path(key));
  std::map<std::string, std::string> values;
  const YAML::Node node = lookup(key);
  if (!node || node.IsNull())
    return values;
  if (!node.IsMap())
    fail(key, "a mapping of names to values");
  for (const auto& item : node) {
    const std::string name = item.first.as<std::string>();
    if (!item.second.IsScalar() && !item.second.IsNull())
      throw InputError(key_path(key) + "." + name + ": expected a single value, got a " +
                       (item.second.IsMap() ? "mapping" : "list"));
    values[name] = item.second.IsNull() ? "" : item.second.Scalar();
  }
  return values;
}

ConfigDocument::ConfigDocument(YAML::Node root, std::string source)
    : root_(std::move(root)), source_(std::move(source)),
      known_(std::make_shared<std::set<std::string>>()),
      free_form_(std::make_shared<std::set<std::string>>()) {}

namespace {
/// A config holds a few hundred values; aliases (&a ... *a) can make a short text stand for
/// exponentially many, which every later walk over the tree would visit.
constexpr std::size_t kMaxConfigValues = 100000;
/// Larger than any hand-written config; keeps a stray multi-gigabyte file out of memory.
constexpr std::uint64_t kMaxConfigBytes = 16ull << 20;
/// Deeper than any config; an alias inside its own anchor (`b: &b [*b]`) makes yaml-cpp build a
/// cycle, whose walk would otherwise overflow the stack before kMaxConfigValues.
constexpr int kMaxConfigDepth = 64;

/// Refuses a key given twice in one mapping (YAML would silently keep the first), a tree that
/// aliases expand beyond kMaxConfigValues and one nested deeper than kMaxConfigDepth. `count` is
/// the number of values visited so far.
void check_tree(const YAML::Node& node, const std::string& path, const std::string& source,
                std::size_t& count, int depth = 0) {
  if (++count > kMaxConfigValues)
    throw InputError(source + ": more than " + std::to_string(kMaxConfigValues) +
                     " values once aliases are expanded; expected a config of plain keys");
  if (depth > kMaxConfigDepth)
    throw InputError(source + ": nested deeper than " + std::to_string(kMaxConfigDepth) +
                     " levels (an alias inside its own anchor?); expected a config of plain keys");
  if (node.IsSequence()) {
    for (const auto& item : node)
      check_tree(item, path, source, count, depth + 1);
    return;
  }
  if (!node.IsMap())
    return;
  std::map<std::string, int> first_line;
  for (const auto& item : node) {
    const int line = item.first.Mark().line + 1;
    if (!item.first.IsScalar())
      throw InputError(source + ":" + std::to_string(line) + ": a key" +
                       (path.empty() ? "" : " under '" + shortened(path) + "'") +
                       " is a list or mapping; expected a plain name");
    const std::string& key = item.first.Scalar();
    const std::string key_path = path.empty() ? key : path + "." + key;
    const auto [seen, inserted] = first_line.emplace(key, line);
    if (!inserted)
      throw InputError(source + ":" + std::to_string(line) + ": key '" + shortened(key_path) +
                       "' given twice (first on line " + std::to_string(seen->second) +
                       "); expected each key once");
    check_tree(item.second, key_path, source, count, depth + 1);
  }
}
/// Where configs find their data: ${TEXSIM_DATA} stands for the environment variable TEXSIM_DATA,
/// or for "data" (the repository's data/, relative to the working directory) when it is unset.
constexpr const char* kDataVariable = "${TEXSIM_DATA}";

std::string data_directory() {
  const char* value = std::getenv("TEXSIM_DATA");
  return value != nullptr && *value != '\0' ? value : "data";
}

/// Replaces ${TEXSIM_DATA} in every scalar of the tree by data_directory().
void expand_data_directory(YAML::Node node) {
  if (node.IsScalar()) {
    std::string text = node.Scalar();
    const std::string variable = kDataVariable;
    bool replaced = false;
    for (auto at = text.find(variable); at != std::string::npos; at = text.find(variable, at + 1)) {
      const auto directory = data_directory();
      text.replace(at, variable.size(), directory);
      at += directory.size() - 1;
      replaced = true;
    }
    if (replaced)
      node = text;
  } else if (node.IsSequence()) {
    for (auto item : node)
      expand_data_directory(item);
  } else if (node.IsMap()) {
    for (auto item : node)
      expand_data_directory(item.second);
  }
}
} // namespace

ConfigDocument ConfigDocument::parse(const std::string& text, const std::string& source) {
  YAML::Node root;
  try {
    root = YAML::Load(text);
  } catch (const YAML::Exception& e) {
    throw InputError(source + ": not valid YAML: " + e.what());
  }
  if (root.IsNull())
    root = YAML::Node(YAML::NodeType::Map);
  if (!root.IsMap())
    throw InputError(source + ": expected a mapping of keys at the top level");
  std::size_t count = 0;
  check_tree(root, "", source, count);
  expand_data_directory(root);
  return ConfigDocument(root, source);
}

ConfigDocument ConfigDocument::load(const std::string& path) {
  return parse(read_regular_file(path, "YAML config file", kMaxConfigBytes), shortened(path));
}

void ConfigDocument::set_override(const std::string& assignment) {
  const auto equals = assignment.find('=');
  if (equals == std::string::npos || equals == 0)
    throw InputError("--set " + assignment + ": expected key.path=value");
  const std::string path = assignment.substr(0, equals);
  YAML::Node value;
  try {
    value = YAML::Load(assignment.substr(equals + 1));
  } catch (const YAML::Exception& e) {
    throw InputError("--set " + assignment + ": the value is not valid YAML: " + e.what());
  }
  expand_data_directory(value);
  std::vector<std::string> keys;
  std::stringstream parts(path);
  for (std::string key; std::getline(parts, key, '.');) {
    if (key.empty())
      throw InputError("--set " + assignment + ": empty component in key path '" + path + "'");
    keys.push_back(key);
  }
  YAML::Node node;
  node.reset(root_);
  for (std::size_t i = 0; i + 1 < keys.size(); ++i) {
    if (!node[keys[i]].IsMap())
      node[keys[i]] = YAML::Node(YAML::NodeType::Map);
    YAML::Node child = node[keys[i]];
    node.reset(child);
  }
  node[keys.back()] = value;
}

ConfigSection ConfigDocument::root() {
  return ConfigSection(this, root_, "");
}

namespace {
// Walks the tree; returns the first key path nobody asked for.
std::optional<std::string> first_unknown(const YAML::Node& node, const std::string& prefix,
                                         const std::set<std::string>& known,
                                         const std::set<std::string>& free_form) {
  for (const auto& item : node) {
    const std::string path = (prefix.empty() ? "" : prefix + ".") + item.first.as<std::string>();
    if (free_form.count(path))
      continue;
    if (!known.count(path))
      return path;
    if (item.second.IsMap())
      if (auto unknown = first_unknown(item.second, path, known, free_form))
        return unknown;
  }
  return std::nullopt;
}
} // namespace

void ConfigDocument::check_unknown_keys() const {
  const auto unknown = first_unknown(root_, "", *known_, *free_form_);
  if (!unknown)
    return;
  const auto dot = unknown->rfind('.');
  const std::string parent = dot == std::string::npos ? "" : unknown->substr(0, dot + 1);
  const std::string leaf = dot == std::string::npos ? *unknown : unknown->substr(dot + 1);
  std::string best;
  std::size_t best_distance = std::string::npos;
  std::vector<std::string> siblings;
  for (const auto& known : *known_) {
    if (known.compare(0, parent.size(), parent) != 0)
      continue;
    const std::string rest = known.substr(parent.size());
    if (rest.find('.') != std::string::npos)
      continue;
    siblings.push_back(rest);
    // Close enough to be a typo: at most half the longer name differs (at least 2 edits allowed).
    const std::size_t distance = edit_distance(leaf, rest);
    const std::size_t allowed = std::max<std::size_t>(2, std::max(leaf.size(), rest.size()) / 2);
    if (distance <= allowed && distance < best_distance) {
      best_distance = distance;
      best = known;
    }
  }
  std::string message = source_ + ": unknown key '" + *unknown + "'";
  if (!best.empty())
    message += " (did you mean '" + best + "'?)";
  else if (!siblings.empty()) {
    message += "; known keys here: ";
    for (std::size_t i = 0; i < siblings.size(); ++i)
      message += (i ? ", " : "") + siblings[i];
  }
  throw InputError(message);
}

std::string ConfigDocument::emit() const {
  YAML::Emitter out;
  out << root_;
  return out.c_str();
}

std::string ConfigDocument::result_hash(const std::vector<std::string>& run_length_keys) const {
  YAML::Node copy = YAML::Clone(root_);
  copy.remove("output");
  copy.remove("checkpoint");
  copy.remove("petsc");
  for (const auto& path : run_length_keys) {
    std::vector<std::string> keys;
    std::stringstream parts(path);
    for (std::string key; std::getline(parts, key, '.');)
      keys.push_back(key);
    YAML::Node node;
    node.reset(copy);
    for (std::size_t i = 0; i + 1 < keys.size() && node.IsMap(); ++i) {
      YAML::Node child = node[keys[i]];
      node.reset(child);
    }
    if (node.IsMap())
      node.remove(keys.back());
  }
  YAML::Emitter out;
  out << copy;
  return hex64(fnv1a64(out.c_str()));
}

} // namespace texsim
