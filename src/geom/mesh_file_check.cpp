#include "geom/mesh_file_check.hpp"

#include "core/error.hpp"
#include "core/input_file.hpp"

#include <algorithm>
#include <bit>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstring>
#include <limits>
#include <optional>
#include <sstream>
#include <string>
#include <string_view>
#include <vector>

namespace texsim::geom {
namespace {

std::string lower_extension(const std::filesystem::path& path) {
  auto ext = path.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return ext;
}

/// Throws InputError "<file>: <parts>".
template <class... Parts>
[[noreturn]] void refuse(const std::filesystem::path& path, const Parts&... parts) {
  std::ostringstream out;
  out << shortened(path.string()) << ": ";
  (out << ... << parts);
  throw InputError(out.str());
}

/// Whitespace-separated words of one line.
std::vector<std::string_view> words_of(std::string_view line) {
  std::vector<std::string_view> words;
  std::size_t pos = 0;
  while (pos < line.size()) {
    while (pos < line.size() && std::isspace(static_cast<unsigned char>(line[pos])))
      ++pos;
    const std::size_t begin = pos;
    while (pos < line.size() && !std::isspace(static_cast<unsigned char>(line[pos])))
      ++pos;
    if (pos > begin)
      words.push_back(line.substr(begin, pos - begin));
  }
  return words;
}

/// Splits text into lines (without the '\n'); `next` returns false at the end.
class Lines {
public:
  explicit Lines(std::string_view text, std::size_t start = 0) : text_(text), pos_(start) {}
  bool next(std::string_view& line) {
    if (pos_ >= text_.size())
      return false;
    const std::size_t end = std::min(text_.find('\n', pos_), text_.size());
    line = text_.substr(pos_, end - pos_);
    pos_ = end + 1;
    ++number_;
    return true;
  }
  std::size_t position() const { return std::min(pos_, text_.size()); }
  std::int64_t number() const { return number_; }

private:
  std::string_view text_;
  std::size_t pos_;
  std::int64_t number_ = 0;
};

template <class Number> std::optional<Number> parse_number(std::string_view word) {
  Number value{};
  const char* first = word.data() + (word.starts_with('+') ? 1 : 0);
  const char* last = word.data() + word.size();
  const auto [end, error] = std::from_chars(first, last, value);
  if (error != std::errc() || end != last)
    return std::nullopt;
  return value;
}

// ---------------------------------------------------------------------------------------------
// PLY

enum class PlyFormat { ascii, binary_little_endian, binary_big_endian };

struct PlyType {
  int bytes = 0;
  bool is_float = false;
  bool is_signed = false;
};

std::optional<PlyType> ply_type(std::string_view name) {
  if (name == "char" || name == "int8")
    return PlyType{1, false, true};
  if (name == "uchar" || name == "uint8")
    return PlyType{1, false, false};
  if (name == "short" || name == "int16")
    return PlyType{2, false, true};
  if (name == "ushort" || name == "uint16")
    return PlyType{2, false, false};
  if (name == "int" || name == "int32")
    return PlyType{4, false, true};
  if (name == "uint" || name == "uint32")
    return PlyType{4, false, false};
  if (name == "float" || name == "float32")
    return PlyType{4, true, true};
  if (name == "double" || name == "float64")
    return PlyType{8, true, true};
  return std::nullopt;
}

struct PlyProperty {
  std::string name;
  PlyType type;
  std::optional<PlyType> list_count; ///< set for `property list COUNT ITEM NAME`
};

struct PlyElement {
  std::string name;
  std::uint64_t count = 0;
  std::vector<PlyProperty> properties;
};

struct PlyHeader {
  PlyFormat format = PlyFormat::ascii;
  std::vector<PlyElement> elements;
  std::size_t body_offset = 0;
  std::int64_t body_line = 0; ///< line number of the body's first line (ASCII)
};

/// VTK 9.1 reads a PLY line with fgets into 4096 bytes and overwrites the last two: a longer line
/// is split, and the piece it reads as a line of its own can be empty.
constexpr std::size_t kPlyLongestLine = 4093;

/// The words of a PLY line as VTK 9.1's reader splits it: on spaces and tabs only (a form feed or
/// a carriage return inside a line joins two numbers into one word), a final '\r' dropped.
std::vector<std::string_view> ply_words_of(std::string_view line) {
  if (line.ends_with('\r'))
    line.remove_suffix(1);
  std::vector<std::string_view> words;
  std::size_t pos = 0;
  while (pos < line.size()) {
    pos = std::min(line.find_first_not_of(" \t", pos), line.size());
    const std::size_t end = std::min(line.find_first_of(" \t", pos), line.size());
    if (end > pos)
      words.push_back(line.substr(pos, end - pos));
    pos = end;
  }
  return words;
}

/// Refuses a PLY text line VTK 9.1 would misread into a crash: a control character other than a
/// tab or a final '\r' (a NUL ends its line early; found by fuzz/), or a line longer than it reads.
void require_readable_ply_line(const std::filesystem::path& path, std::string_view line,
                               const std::string& where) {
  const std::string_view content = line.ends_with('\r') ? line.substr(0, line.size() - 1) : line;
  const auto control = std::find_if(content.begin(), content.end(), [](char c) {
    return static_cast<unsigned char>(c) < 0x20 && c != '\t';
  });
  if (control != content.end())
    refuse(path, where, " holds the control byte ", int(static_cast<unsigned char>(*control)),
           " at column ", control - content.begin() + 1,
           "; expected text whose words are separated by spaces or tabs");
  if (line.size() > kPlyLongestLine)
    refuse(path, where, " is ", line.size(),
           " bytes long; VTK's PLY reader reads lines of at most ", kPlyLongestLine, " bytes");
}

constexpr const char* kPlyTypes = "char uchar short ushort int uint float double (or int8 ... "
                                  "float64)";

PlyHeader parse_ply_header(const std::filesystem::path& path, std::string_view text) {
  PlyHeader header;
  Lines lines(text);
  std::string_view line;
  if (!lines.next(line) || ply_words_of(line) != std::vector<std::string_view>{"ply"})
    refuse(path, "does not start with the line 'ply'; not a PLY file");
  bool has_format = false;
  bool ended = false;
  while (!ended && lines.next(line)) {
    const auto where = [&] { return "header line " + std::to_string(lines.number()); };
    require_readable_ply_line(path, line, where());
    const auto words = ply_words_of(line);
    // VTK 9.1's reader dereferences the missing first word of a blank line (found by fuzz/).
    if (words.empty())
      refuse(path, where(), " is blank; expected a keyword on every header line");
    if (words[0] == "comment" || words[0] == "obj_info")
      continue;
    if (words[0] == "end_header") {
      ended = true;
    } else if (words[0] == "format") {
      if (words.size() != 3 || words[2] != "1.0")
        refuse(path, where(), ": '", line, "'; expected 'format ascii|binary_little_endian|",
               "binary_big_endian 1.0'");
      if (words[1] == "ascii")
        header.format = PlyFormat::ascii;
      else if (words[1] == "binary_little_endian")
        header.format = PlyFormat::binary_little_endian;
      else if (words[1] == "binary_big_endian")
        header.format = PlyFormat::binary_big_endian;
      else
        refuse(path, where(), ": format '", words[1],
               "'; expected ascii, binary_little_endian or binary_big_endian");
      has_format = true;
    } else if (words[0] == "element") {
      const auto count = words.size() == 3 ? parse_number<std::int64_t>(words[2]) : std::nullopt;
      if (!count || *count < 0 || *count > std::numeric_limits<std::int32_t>::max())
        refuse(path, where(), ": '", shortened(std::string(line)),
               "'; expected 'element NAME COUNT' with a count in [0, 2^31 - 1]");
      for (const auto& element : header.elements)
        if (element.name == words[1])
          refuse(path, where(), ": element '", words[1], "' declared twice");
      header.elements.push_back({std::string(words[1]), std::uint64_t(*count), {}});
    } else if (words[0] == "property") {
      if (header.elements.empty())
        refuse(path, where(), ": property before any element");
      PlyProperty property;
      std::optional<PlyType> type;
      if (words.size() == 5 && words[1] == "list") {
        property.list_count = ply_type(words[2]);
        type = ply_type(words[3]);
        if (!property.list_count || property.list_count->is_float || !type)
          refuse(path, where(), ": '", shortened(std::string(line)),
                 "'; expected 'property list COUNT_TYPE ITEM_TYPE NAME' with an integer count "
                 "type, types among ",
                 kPlyTypes);
        property.name = words[4];
      } else if (words.size() == 3 && (type = ply_type(words[1]))) {
        property.name = words[2];
      } else {
        refuse(path, where(), ": '", shortened(std::string(line)),
               "'; expected 'property TYPE NAME' with TYPE among ", kPlyTypes);
      }
      property.type = *type;
      for (const auto& other : header.elements.back().properties)
        if (other.name == property.name)
          refuse(path, where(), ": property '", shortened(property.name, 40), "' of element '",
                 shortened(header.elements.back().name, 40), "' declared twice");
      header.elements.back().properties.push_back(property);
    }
    // Like VTK, other lines are ignored: exporters write free text there ("Created by ...").
  }
  if (!ended)
    refuse(path, "PLY header has no 'end_header' line");
  // VTK 9.1's reader crashes on an element without properties (found by fuzz/).
  for (const auto& element : header.elements)
    if (element.properties.empty())
      refuse(path, "PLY element '", shortened(element.name, 40),
             "' has no properties; expected at least one");
  if (!has_format)
    refuse(path, "PLY header has no 'format' line");
  header.body_offset = lines.position();
  header.body_line = lines.number() + 1;
  return header;
}

/// Which property of the vertex element is x, y, z (-1 where absent), and of the face element the
/// vertex index list.
struct PlyRoles {
  const PlyElement* vertex = nullptr;
  const PlyElement* face = nullptr;
  std::vector<int> coordinate; ///< per property of the vertex element: axis 0-2, or -1
  int indices = -1;            ///< property of the face element holding the vertex indices
};

std::string element_order(const PlyHeader& header) {
  std::string order;
  for (const auto& element : header.elements)
    order += (order.empty() ? "" : ", ") + shortened(element.name, 40);
  return order;
}

PlyRoles find_roles(const std::filesystem::path& path, const PlyHeader& header) {
  PlyRoles roles;
  for (const auto& element : header.elements) {
    if (element.name == "vertex")
      roles.vertex = &element;
    if (element.name == "face")
      roles.face = &element;
  }
  if (roles.vertex == nullptr)
    refuse(path, "PLY header has no 'vertex' element; expected one with x, y and z");
  // VTK 9.1's reader crashes on any other order (found by fuzz/): vertex first, then face.
  const PlyElement* second = header.elements.size() > 1 ? &header.elements[1] : nullptr;
  if (roles.vertex != &header.elements.front() || (roles.face != nullptr && roles.face != second))
    refuse(path, "PLY elements in the order ", element_order(header),
           "; expected vertex first, then face, then any others");
  int found = 0;
  for (const auto& property : roles.vertex->properties) {
    const auto& n = property.name;
    const int axis = n == "x" ? 0 : n == "y" ? 1 : n == "z" ? 2 : -1;
    // VTK 9.1's reader crashes on any list property of the vertex element (found by fuzz/).
    if (property.list_count)
      refuse(path, "PLY vertex property '", shortened(n, 40),
             "' is a list; expected numbers only in the vertex element");
    roles.coordinate.push_back(axis);
    found += axis >= 0;
  }
  if (found != 3)
    refuse(path, "PLY vertex element lacks some of the properties x, y, z");
  if (roles.face != nullptr) {
    for (std::size_t p = 0; p < roles.face->properties.size(); ++p) {
      const auto& property = roles.face->properties[p];
      if (property.list_count &&
          (property.name == "vertex_indices" || property.name == "vertex_index"))
        roles.indices = static_cast<int>(p);
    }
    if (roles.indices < 0 || roles.face->properties[roles.indices].type.is_float)
      refuse(path, "PLY face element has no integer list property vertex_indices");
  }
  return roles;
}

/// Reads the body value by value (binary) or line by line (ASCII), checking that every declared
/// value is present, coordinates are finite and face indices name existing vertices.
class PlyBodyWalker {
public:
  PlyBodyWalker(const std::filesystem::path& path, std::string_view text, const PlyHeader& header,
                const PlyRoles& roles)
      : path_(path), text_(text), header_(header), roles_(roles), pos_(header.body_offset),
        swap_((header.format == PlyFormat::binary_big_endian) !=
              (std::endian::native == std::endian::big)) {}

  void walk() {
    Lines lines(text_, header_.body_offset);
    for (const auto& element : header_.elements)
      for (std::uint64_t i = 0; i < element.count; ++i) {
        if (header_.format == PlyFormat::ascii)
          next_ascii_line(lines, element, i);
        for (std::size_t p = 0; p < element.properties.size(); ++p)
          read_property(element, i, p);
      }
  }

private:
  void next_ascii_line(Lines& lines, const PlyElement& element, std::uint64_t i) {
    std::string_view line;
    if (!lines.next(line))
      truncated(element, i);
    require_readable_ply_line(path_, line,
                              "PLY " + element.name + " " + std::to_string(i) + " (line " +
                                  std::to_string(header_.body_line + lines.number() - 1) + ")");
    words_ = ply_words_of(line);
    word_ = 0;
    // VTK 9.1's reader frees memory it does not own on an empty line (found by fuzz/).
    if (words_.empty())
      refuse(path_, "PLY ", element.name, " ", i, " is an empty line (line ",
             header_.body_line + lines.number() - 1, "); expected one element per line");
  }

  [[noreturn]] void truncated(const PlyElement& element, std::uint64_t i) const {
    refuse(path_, "PLY body ends in ", element.name, " ", i, " of the ", element.count,
           " the header declares (", text_.size() - header_.body_offset,
           " bytes after the header)");
  }

  double value(const PlyType& type, const PlyElement& element, std::uint64_t i) {
    if (header_.format == PlyFormat::ascii) {
      if (word_ >= words_.size())
        refuse(path_, "PLY ", element.name, " ", i, " has ", words_.size(),
               " values on its line; the header declares more");
      const auto word = words_[word_++];
      std::optional<double> number = parse_number<double>(word);
      if (!type.is_float) {
        const auto integer = parse_number<std::int64_t>(word);
        number = integer ? std::optional<double>(double(*integer)) : std::nullopt;
      }
      if (!number)
        refuse(path_, "PLY ", element.name, " ", i, ": '", shortened(std::string(word)), "' where ",
               type.is_float ? "a number" : "an integer", " was expected");
      return *number;
    }
    if (text_.size() - pos_ < std::size_t(type.bytes))
      truncated(element, i);
    unsigned char bytes[8];
    std::memcpy(bytes, text_.data() + pos_, type.bytes);
    pos_ += type.bytes;
    if (swap_)
      std::reverse(bytes, bytes + type.bytes);
    return decode(bytes, type);
  }

  static double decode(const unsigned char* b, const PlyType& type) {
    const auto as = [b]<class T>(T) {
      T v;
      std::memcpy(&v, b, sizeof v);
      return double(v);
    };
    if (type.is_float)
      return type.bytes == 4 ? as(float{}) : as(double{});
    switch (type.bytes) {
    case 1:
      return type.is_signed ? as(std::int8_t{}) : as(std::uint8_t{});
    case 2:
      return type.is_signed ? as(std::int16_t{}) : as(std::uint16_t{});
    default:
      return type.is_signed ? as(std::int32_t{}) : as(std::uint32_t{});
    }
  }

  void read_property(const PlyElement& element, std::uint64_t i, std::size_t p) {
    const PlyProperty& property = element.properties[p];
    if (!property.list_count) {
      const double v = value(property.type, element, i);
      if (&element == roles_.vertex && roles_.coordinate[p] >= 0 && !std::isfinite(v))
        refuse(path_, "PLY vertex ", i, " has ", property.name, " = ", v,
               "; expected finite coordinates");
      return;
    }
    const double length = value(*property.list_count, element, i);
    if (length < 0)
      refuse(path_, "PLY ", element.name, " ", i, " has a list of ", length, " items");
    const bool indices = &element == roles_.face && int(p) == roles_.indices;
    for (std::int64_t k = 0; k < std::int64_t(length); ++k) {
      const double v = value(property.type, element, i);
      if (indices && (v < 0 || v >= double(roles_.vertex->count)))
        refuse(path_, "PLY face ", i, " names vertex ", v, "; the file has ", roles_.vertex->count,
               " vertices");
    }
  }

  const std::filesystem::path& path_;
  std::string_view text_;
  const PlyHeader& header_;
  const PlyRoles& roles_;
  std::size_t pos_;
  bool swap_;
  std::vector<std::string_view> words_;
  std::size_t word_ = 0;
};

MeshFileCounts check_ply(const std::filesystem::path& path, std::string_view text) {
  const PlyHeader header = parse_ply_header(path, text);
  const PlyRoles roles = find_roles(path, header);
  PlyBodyWalker(path, text, header, roles).walk();
  const bool last_line_is_text =
      header.format == PlyFormat::ascii || header.body_offset >= text.size();
  return {roles.vertex->count, roles.face != nullptr ? roles.face->count : 0,
          last_line_is_text && !text.ends_with('\n')};
}

// ---------------------------------------------------------------------------------------------
// STL

/// VTK decides between ASCII and binary STL as vtksys::SystemTools::DetectFileType does: binary
/// when at least 5% of the first 256 bytes are not text, text being 0x20-0x7F, tab, line feed
/// and carriage return (so vertical tab and form feed count as binary, unlike for isspace).
bool looks_binary(std::string_view text) {
  const std::size_t n = std::min<std::size_t>(text.size(), 256);
  std::size_t other = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const auto c = static_cast<unsigned char>(text[i]);
    other += !((c >= 0x20 && c <= 0x7F) || c == '\t' || c == '\n' || c == '\r');
  }
  return n > 0 && double(other) / double(n) >= 0.05;
}

/// ASCII STL, line by line: "solid NAME", then per triangle "facet normal N N N", "outer loop",
/// three "vertex X Y Z" with finite numbers, "endloop", "endfacet"; "endsolid NAME" (several
/// solids may follow each other). VTK 9.1's reader runs out of memory on text outside this grammar
/// (found by fuzz/).
MeshFileCounts check_ascii_stl(const std::filesystem::path& path, std::string_view text) {
  enum class Expect { solid, facet, loop, vertex, endloop, endfacet };
  static constexpr const char* kExpected[] = {
      "solid", "facet normal or endsolid", "outer loop", "vertex X Y Z", "endloop", "endfacet"};
  Expect expect = Expect::solid;
  int corners = 0;
  MeshFileCounts counts;
  Lines lines(text);
  std::string_view line;
  while (lines.next(line)) {
    const auto words = words_of(line);
    if (words.empty())
      continue;
    const auto bad = [&] {
      refuse(path, lines.number(), ": '", shortened(std::string(line), 80), "'; expected ",
             kExpected[int(expect)], " (ASCII STL)");
    };
    switch (expect) {
    case Expect::solid:
      if (words[0] != "solid")
        bad();
      expect = Expect::facet;
      break;
    case Expect::facet:
      if (words[0] == "endsolid") {
        expect = Expect::solid;
        break;
      }
      if (words[0] != "facet" || words.size() != 5 || words[1] != "normal")
        bad();
      expect = Expect::loop;
      break;
    case Expect::loop:
      if (words.size() != 2 || words[0] != "outer" || words[1] != "loop")
        bad();
      expect = Expect::vertex;
      corners = 0;
      break;
    case Expect::vertex:
      if (words[0] != "vertex" || words.size() != 4)
        bad();
      for (std::size_t axis = 1; axis < 4; ++axis) {
        const auto v = parse_number<double>(words[axis]);
        if (!v || !std::isfinite(*v))
          refuse(path, lines.number(), ": '", shortened(std::string(line), 80),
                 "'; expected 'vertex X Y Z' with three finite numbers");
      }
      ++counts.vertices;
      expect = ++corners == 3 ? Expect::endloop : Expect::vertex;
      break;
    case Expect::endloop:
      if (words.size() != 1 || words[0] != "endloop")
        bad();
      expect = Expect::endfacet;
      break;
    case Expect::endfacet:
      if (words.size() != 1 || words[0] != "endfacet")
        bad();
      ++counts.faces;
      expect = Expect::facet;
      break;
    }
  }
  if (expect != Expect::solid && expect != Expect::facet)
    refuse(path, "ASCII STL ends inside a facet; expected ", kExpected[int(expect)]);
  return counts;
}

MeshFileCounts check_stl(const std::filesystem::path& path, std::string_view text) {
  if (text.empty())
    refuse(path, "empty file; expected an STL mesh");
  if (looks_binary(text)) {
    if (text.size() < 84)
      refuse(path, text.size(), " bytes; a binary STL has at least an 84-byte header");
    // The triangle count is a little-endian uint32 after the 80-byte header.
    std::uint32_t count = 0;
    for (int b = 3; b >= 0; --b)
      count = (count << 8) | static_cast<unsigned char>(text[80 + b]);
    const std::uint64_t needed = 84 + 50 * std::uint64_t(count);
    if (text.size() < needed)
      refuse(path, "binary STL header declares ", count, " triangles (", needed,
             " bytes) but the file has ", text.size(), " bytes");
    return {3 * std::uint64_t(count), count};
  }
  return check_ascii_stl(path, text);
}

// ---------------------------------------------------------------------------------------------
// OBJ

/// Index `word` (before any '/') of an OBJ face corner, checked against `count` elements
/// defined so far (negative indices count back from the last one).
void check_obj_index(const std::filesystem::path& path, std::int64_t line, std::string_view word,
                     std::uint64_t count, const char* kind, const char* kinds) {
  if (word.empty())
    return;
  const auto index = parse_number<std::int64_t>(word);
  if (!index || *index == 0 || (*index > 0 && std::uint64_t(*index) > count) ||
      (*index < 0 && std::uint64_t(-*index) > count))
    refuse(path, line, ": face refers to ", kind, " '", shortened(std::string(word)), "' but only ",
           count, " ", kinds, " are defined before it; expected 1..", count, " or -1..-", count);
}

/// Which indices an OBJ face corner gives: "v", "v/vt", "v//vn", "v/vt/vn" (and "v/" etc.).
std::string corner_form(std::string_view corner) {
  std::string form;
  bool in_number = false;
  for (const char c : corner) {
    if (c == '/') {
      form += '/';
      in_number = false;
    } else if (!in_number) {
      form += 'n';
      in_number = true;
    }
  }
  return form;
}

MeshFileCounts check_obj(const std::filesystem::path& path, std::string_view text) {
  MeshFileCounts counts;
  std::uint64_t texture_coordinates = 0, normals = 0;
  Lines lines(text);
  std::string_view line;
  while (lines.next(line)) {
    const auto words = words_of(line);
    if (words.empty())
      continue;
    if (words[0] == "v") {
      ++counts.vertices;
      for (std::size_t axis = 1; axis < 4; ++axis) {
        const auto v = axis < words.size() ? parse_number<double>(words[axis]) : std::nullopt;
        if (!v || !std::isfinite(*v))
          refuse(path, lines.number(), ": '", shortened(std::string(line)),
                 "'; expected 'v X Y Z' with three finite numbers");
      }
    } else if (words[0] == "vt") {
      ++texture_coordinates;
    } else if (words[0] == "vn") {
      ++normals;
    } else if (words[0] == "f") {
      ++counts.faces;
      for (std::size_t k = 1; k < words.size(); ++k) {
        const auto corner = words[k];
        // VTK 9.1's reader crashes when corners of one face differ in form (found by fuzz/).
        if (corner_form(corner) != corner_form(words[1]))
          refuse(path, lines.number(), ": face corners '", shortened(std::string(words[1]), 40),
                 "' and '", shortened(std::string(corner), 40),
                 "' differ in form; expected all v, v/vt, v//vn or v/vt/vn");
        const auto slash = corner.find('/');
        check_obj_index(path, lines.number(), corner.substr(0, slash), counts.vertices, "vertex",
                        "vertices");
        if (slash == std::string_view::npos)
          continue;
        const auto rest = corner.substr(slash + 1);
        const auto second = rest.find('/');
        check_obj_index(path, lines.number(), rest.substr(0, second), texture_coordinates,
                        "texture coordinate", "texture coordinates");
        if (second != std::string_view::npos)
          check_obj_index(path, lines.number(), rest.substr(second + 1), normals, "normal",
                          "normals");
      }
    }
  }
  return counts;
}

// ---------------------------------------------------------------------------------------------
// OFF: the counts of the header (read_off() checks the whole file when it reads it).

MeshFileCounts off_counts(std::string_view text) {
  std::vector<std::string_view> words;
  Lines lines(text);
  std::string_view line;
  while (words.size() < 3 && lines.next(line)) {
    const auto hash = line.find('#');
    for (const auto word : words_of(line.substr(0, hash)))
      words.push_back(word);
  }
  MeshFileCounts counts;
  if (words.size() >= 3) {
    counts.vertices = parse_number<std::uint64_t>(words[1]).value_or(0);
    counts.faces = parse_number<std::uint64_t>(words[2]).value_or(0);
  }
  return counts;
}

} // namespace

MeshFileCounts check_mesh_file(const std::filesystem::path& path) {
  const std::string ext = lower_extension(path);
  const std::uint64_t size = require_regular_file(path, "mesh file");
  if (ext != ".vtk" && ext != ".vtp" && ext != ".vtu" && ext != ".ply" && ext != ".stl" &&
      ext != ".obj" && ext != ".off")
    refuse(path, "unknown mesh extension '", shortened(ext),
           "'; expected one of .obj .ply .stl .vtk .vtp .vtu .off");
  if (ext != ".ply" && ext != ".stl" && ext != ".obj" && ext != ".off") {
    // VTK's formats: at least 12 bytes per vertex (three float32), two triangles per vertex.
    return {size / 12, size / 6};
  }
  const std::string text = read_regular_file(path, "mesh file", size);
  if (ext == ".ply")
    return check_ply(path, text);
  if (ext == ".stl")
    return check_stl(path, text);
  if (ext == ".obj")
    return check_obj(path, text);
  return off_counts(text);
}

} // namespace texsim::geom
