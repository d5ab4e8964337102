#pragma once
/// A user formula evaluated at many points or cells (muparser, bulk mode): `x`, `y`, `z` and any
/// per-point arrays the caller names (species values, earlier stages' results). Turk's controls are
/// such formulas: which cells a cascade stage may change, where diffusion is faster, what is
/// rendered; so is the texture orientation field of surface_synthesis.
#include <memory>
#include <span>
#include <string>
#include <vector>

namespace mu {
class Parser;
}

namespace texsim::geom {

class PointExpression {
public:
  /// Parses `text` with the variables x, y, z and `names`; throws InputError
  /// "<key_path>: cannot parse "...": ..." for syntax errors and unknown variables.
  PointExpression(const std::string& text, std::vector<std::string> names,
                  const std::string& key_path);
  ~PointExpression();
  PointExpression(PointExpression&&) noexcept;
  PointExpression& operator=(PointExpression&&) noexcept;

  /// Value at every cell: xyz holds 3 coordinates per cell, columns[k][i] the value of names[k]
  /// at cell i. Not thread-safe.
  std::vector<double> evaluate(std::span<const double> xyz,
                               const std::vector<std::span<const double>>& columns) const;

  const std::string& text() const { return text_; }
  /// Whether the formula reads the variable `name`.
  bool uses(const std::string& name) const;

private:
  std::string text_;
  std::vector<std::string> names_;
  std::string key_path_;
  // Bound variable storage: the parser reads variable k of cell i at data() + i.
  mutable std::vector<std::vector<double>> bound_;
  std::unique_ptr<mu::Parser> parser_;
  void bind(std::size_t cells) const;
};

} // namespace texsim::geom
