#include "geom/point_expression.hpp"

#include "core/error.hpp"

#include <muParser.h>

namespace texsim::geom {
namespace {
constexpr std::size_t kCoordinates = 3; // x, y, z come first in bound_
}

PointExpression::PointExpression(const std::string& text, std::vector<std::string> names,
                                 const std::string& key_path)
    : text_(text), names_(std::move(names)), key_path_(key_path),
      bound_(kCoordinates + names_.size()), parser_(std::make_unique<mu::Parser>()) {
  bind(1);
  try {
    parser_->SetExpr(text_);
    parser_->Eval();
  } catch (const mu::Parser::exception_type& error) {
    throw InputError(key_path_ + ": cannot parse \"" + text_ + "\": " + error.GetMsg());
  }
}

PointExpression::~PointExpression() = default;
PointExpression::PointExpression(PointExpression&&) noexcept = default;
PointExpression& PointExpression::operator=(PointExpression&&) noexcept = default;

void PointExpression::bind(std::size_t cells) const {
  if (!bound_[0].empty() && bound_[0].size() >= cells)
    return;
  for (auto& column : bound_)
    column.assign(std::max<std::size_t>(cells, 1), 0.0);
  const char* axes[kCoordinates] = {"x", "y", "z"};
  try {
    for (std::size_t k = 0; k < kCoordinates; ++k)
      parser_->DefineVar(axes[k], bound_[k].data());
    for (std::size_t k = 0; k < names_.size(); ++k)
      parser_->DefineVar(names_[k], bound_[kCoordinates + k].data());
  } catch (const mu::Parser::exception_type& error) {
    throw InputError(key_path_ + ": " + error.GetMsg());
  }
}

bool PointExpression::uses(const std::string& name) const {
  const auto& used = parser_->GetUsedVar();
  return used.find(name) != used.end();
}

std::vector<double>
PointExpression::evaluate(std::span<const double> xyz,
                          const std::vector<std::span<const double>>& columns) const {
  const std::size_t cells = xyz.size() / kCoordinates;
  TEXSIM_VERIFY(columns.size() == names_.size(), key_path_ << ": " << columns.size()
                                                           << " columns for " << names_.size()
                                                           << " names");
  std::vector<double> result(cells);
  if (cells == 0)
    return result;
  bind(cells);
  for (std::size_t i = 0; i < cells; ++i)
    for (std::size_t k = 0; k < kCoordinates; ++k)
      bound_[k][i] = xyz[kCoordinates * i + k];
  for (std::size_t k = 0; k < names_.size(); ++k)
    std::copy(columns[k].begin(), columns[k].begin() + cells, bound_[kCoordinates + k].begin());
  try {
    parser_->Eval(result.data(), int(cells));
  } catch (const mu::Parser::exception_type& error) {
    throw InputError(key_path_ + ": cannot evaluate \"" + text_ + "\": " + error.GetMsg());
  }
  return result;
}

} // namespace texsim::geom
