#include "geom/off_reader.hpp"

#include "core/error.hpp"

#include <charconv>
#include <cmath>
#include <cstdint>
#include <fstream>
#include <iterator>
#include <limits>
#include <sstream>
#include <string>
#include <string_view>
#include <vector>

namespace texsim::geom {
namespace {

/// Whitespace-separated tokens of an OFF file with their line numbers; comments are skipped.
class OffTokens {
public:
  OffTokens(std::filesystem::path path, std::string text)
      : path_(std::move(path)), text_(std::move(text)) {}

  /// Next token on any line; throws naming `expected` at the end of the file.
  std::string_view next(const char* expected) {
    skip_space(true);
    if (pos_ >= text_.size()) {
      TEXSIM_INPUT_ERROR(path_.string()
                         << ":" << line_ << ": file ends where " << expected << " was expected");
    }
    const auto begin = pos_;
    while (pos_ < text_.size() && !is_space(text_[pos_]) && text_[pos_] != '#') {
      ++pos_;
    }
    return std::string_view(text_).substr(begin, pos_ - begin);
  }

  /// True when the current line holds another token.
  bool more_on_line() {
    skip_space(false);
    return pos_ < text_.size() && text_[pos_] != '\n';
  }

  /// Drops the rest of the current line (extra per-vertex or per-face data).
  void skip_line() {
    while (pos_ < text_.size() && text_[pos_] != '\n') {
      ++pos_;
    }
  }

  /// A finite floating-point number (from_chars also reads "nan" and "inf").
  double coordinate() {
    const double value = number<double>("a vertex coordinate");
    if (!std::isfinite(value)) {
      fail(value, " where a finite vertex coordinate was expected");
    }
    return value;
  }

  template <class Number> Number number(const char* expected) {
    const auto token = next(expected);
    Number value{};
    const auto* first = token.data() + (token.starts_with('+') ? 1 : 0);
    const auto* last = token.data() + token.size();
    const auto [end, error] = std::from_chars(first, last, value);
    if (error != std::errc() || end != last) {
      fail("'", token, "' where ", expected, " was expected");
    }
    return value;
  }

  /// Throws InputError "file:line: <parts>".
  template <class... Parts> [[noreturn]] void fail(const Parts&... parts) const {
    std::ostringstream out;
    out << path_.string() << ":" << line_ << ": ";
    (out << ... << parts);
    throw InputError(out.str());
  }

  std::size_t size() const { return text_.size(); }

private:
  static bool is_space(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\n'; }

  void skip_space(bool cross_lines) {
    while (pos_ < text_.size()) {
      const char c = text_[pos_];
      if (c == '#') {
        skip_line();
      } else if (c == '\n' && cross_lines) {
        ++line_;
        ++pos_;
      } else if (c == ' ' || c == '\t' || c == '\r') {
        ++pos_;
      } else {
        return;
      }
    }
  }

  std::filesystem::path path_;
  std::string text_;
  std::size_t pos_ = 0;
  std::int64_t line_ = 1;
};

} // namespace

TriangleMesh read_off(const std::filesystem::path& path) {
  std::ifstream file(path, std::ios::binary);
  if (!file) {
    TEXSIM_INPUT_ERROR(path.string() << ": cannot open the file; expected a readable .off mesh");
  }
  OffTokens tokens(path, std::string(std::istreambuf_iterator<char>(file), {}));

  const auto keyword = tokens.next("the OFF header");
  if (keyword != "OFF" && keyword != "COFF") {
    if (keyword.ends_with("OFF")) {
      tokens.fail("header '", keyword,
                  "': normal, 4D and texture-coordinate OFF variants are not supported; expected "
                  "OFF or COFF");
    }
    tokens.fail("header '", keyword, "'; expected OFF or COFF");
  }
  const auto n_vertices = tokens.number<std::int64_t>("the vertex count");
  const auto n_faces = tokens.number<std::int64_t>("the face count");
  if (tokens.more_on_line()) {
    tokens.number<std::int64_t>("the edge count");
  }
  // Every vertex takes at least 6 characters ("0 0 0\n") and every face 8 ("3 0 1 2\n").
  const auto max_count = static_cast<std::int64_t>(tokens.size() / 6);
  if (n_vertices <= 0 || n_faces < 0 || n_vertices > max_count || n_faces > max_count ||
      n_vertices > std::numeric_limits<std::int32_t>::max()) {
    tokens.fail("header declares ", n_vertices, " vertices and ", n_faces,
                " faces; expected positive counts that a file of ", tokens.size(),
                " bytes can hold");
  }
  TriangleMesh mesh;
  mesh.positions.resize(n_vertices);
  for (auto& p : mesh.positions) {
    for (int axis = 0; axis < 3; ++axis) {
      p[axis] = tokens.coordinate();
    }
    tokens.skip_line();
  }
  mesh.triangles.reserve(n_faces);
  std::vector<std::int32_t> polygon;
  for (std::int64_t f = 0; f < n_faces; ++f) {
    const auto corners = tokens.number<std::int64_t>("a face's vertex count");
    if (corners < 3 || corners > n_vertices) {
      tokens.fail("face ", f, " has ", corners, " vertices; expected a polygon of at least 3");
    }
    polygon.resize(corners);
    for (auto& v : polygon) {
      v = tokens.number<std::int32_t>("a face's vertex index");
    }
    tokens.skip_line();
    for (std::int64_t i = 1; i + 1 < corners; ++i) {
      mesh.triangles.push_back({polygon[0], polygon[i], polygon[i + 1]});
    }
  }
  return mesh;
}

} // namespace texsim::geom
