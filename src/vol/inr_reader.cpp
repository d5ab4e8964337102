#include "vol/inr_reader.hpp"

#include "core/input_file.hpp"
#include "vol/grid_checks.hpp"

#include <algorithm>
#include <array>
#include <bit>
#include <charconv>
#include <cstdint>
#include <cstring>
#include <map>
#include <string>
#include <vector>

namespace texsim::vol {
namespace {

constexpr std::size_t kBlock = 256;
constexpr std::string_view kMagic = "#INRIMAGE-4#{";
constexpr std::string_view kEnd = "##}\n";

enum class Sample { float32, float64, uint8, uint16, uint32, int8, int16, int32 };

struct Header {
  std::size_t bytes = 0; // header length, a multiple of 256
  Dims dims;
  int vdim = 1;
  Sample sample = Sample::float32;
  bool big_endian = false;
  std::array<double, 3> spacing{1.0, 1.0, 1.0};
};

std::size_t sample_bytes(Sample s) {
  switch (s) {
  case Sample::uint8:
  case Sample::int8:
    return 1;
  case Sample::uint16:
  case Sample::int16:
    return 2;
  case Sample::float64:
    return 8;
  default:
    return 4;
  }
}

class HeaderParser {
public:
  HeaderParser(const std::filesystem::path& path, std::map<std::string, std::string> fields)
      : path_(path), fields_(std::move(fields)) {}

  bool has(const std::string& key) const { return fields_.count(key) > 0; }

  const std::string& text(const std::string& key) const {
    const auto it = fields_.find(key);
    if (it == fields_.end()) {
      TEXSIM_INPUT_ERROR(path_.string() << ": INRIMAGE header has no " << key << " field");
    }
    return it->second;
  }

  int positive_int(const std::string& key) const {
    const std::string& value = text(key);
    int n = 0;
    const auto [end, ec] = std::from_chars(value.data(), value.data() + value.size(), n);
    if (ec != std::errc() || end != value.data() + value.size() || n <= 0) {
      TEXSIM_INPUT_ERROR(path_.string() << ": INRIMAGE field " << key << "=" << value
                                        << ", expected a positive integer");
    }
    return n;
  }

  double positive_double(const std::string& key, double fallback) const {
    if (!has(key)) {
      return fallback;
    }
    const std::string& value = text(key);
    std::size_t used = 0;
    double v = 0.0;
    try {
      v = std::stod(value, &used);
    } catch (const std::exception&) {
      used = 0;
    }
    if (used != value.size() || !(v > 0.0)) {
      TEXSIM_INPUT_ERROR(path_.string() << ": INRIMAGE field " << key << "=" << value
                                        << ", expected a positive number");
    }
    return v;
  }

  [[noreturn]] void bad(const std::string& key, const std::string& expected) const {
    TEXSIM_INPUT_ERROR(path_.string() << ": INRIMAGE field " << key << "=" << text(key)
                                      << ", expected " << expected);
  }

private:
  const std::filesystem::path& path_;
  std::map<std::string, std::string> fields_;
};

Header parse_header(const std::filesystem::path& path, const std::string& bytes) {
  if (bytes.compare(0, kMagic.size(), kMagic) != 0) {
    TEXSIM_INPUT_ERROR(path.string()
                       << ": file does not start with '" << kMagic << "', not an INRIMAGE-4 file");
  }
  const std::size_t end = bytes.find(kEnd);
  if (end == std::string::npos) {
    TEXSIM_INPUT_ERROR(path.string() << ": INRIMAGE header is not closed by '##}'");
  }
  Header header;
  header.bytes = end + kEnd.size();
  if (header.bytes % kBlock != 0) {
    TEXSIM_INPUT_ERROR(path.string() << ": INRIMAGE header is " << header.bytes
                                     << " bytes long, expected a multiple of " << kBlock);
  }
  std::map<std::string, std::string> fields;
  std::size_t line_start = kMagic.size();
  while (line_start < end) {
    std::size_t line_end = bytes.find('\n', line_start);
    const std::string line = bytes.substr(line_start, line_end - line_start);
    line_start = line_end + 1;
    if (line.empty() || line[0] == '#') {
      continue;
    }
    const std::size_t eq = line.find('=');
    if (eq == std::string::npos || eq == 0) {
      TEXSIM_INPUT_ERROR(path.string()
                         << ": INRIMAGE header line '" << line << "', expected KEY=VALUE");
    }
    fields[line.substr(0, eq)] = line.substr(eq + 1);
  }

  const HeaderParser parser(path, std::move(fields));
  header.dims = {parser.positive_int("XDIM"), parser.positive_int("YDIM"),
                 parser.positive_int("ZDIM")};
  header.vdim = parser.has("VDIM") ? parser.positive_int("VDIM") : 1;
  if (header.vdim != 1 && header.vdim != 3) {
    parser.bad("VDIM", "1 (scalar) or 3 (RGB)");
  }
  const std::string& type = parser.text("TYPE");
  const std::string& pixsize = parser.text("PIXSIZE");
  const int bits = pixsize == "8 bits"    ? 8
                   : pixsize == "16 bits" ? 16
                   : pixsize == "32 bits" ? 32
                   : pixsize == "64 bits" ? 64
                                          : 0;
  if (bits == 0) {
    parser.bad("PIXSIZE", "'8 bits', '16 bits', '32 bits' or '64 bits'");
  }
  if (type == "float") {
    if (bits != 32 && bits != 64) {
      parser.bad("PIXSIZE", "'32 bits' or '64 bits' for TYPE=float");
    }
    header.sample = bits == 32 ? Sample::float32 : Sample::float64;
  } else if (type == "unsigned fixed" || type == "signed fixed") {
    if (bits == 64) {
      parser.bad("PIXSIZE", "8, 16 or 32 bits for TYPE=" + type);
    }
    const bool is_signed = type == "signed fixed";
    header.sample = bits == 8    ? (is_signed ? Sample::int8 : Sample::uint8)
                    : bits == 16 ? (is_signed ? Sample::int16 : Sample::uint16)
                                 : (is_signed ? Sample::int32 : Sample::uint32);
  } else {
    parser.bad("TYPE", "'float', 'unsigned fixed' or 'signed fixed'");
  }
  if (parser.has("CPU")) {
    const std::string& cpu = parser.text("CPU");
    if (cpu == "sun" || cpu == "sgi") {
      header.big_endian = true;
    } else if (cpu != "decm" && cpu != "alpha" && cpu != "pc") {
      parser.bad("CPU", "decm, alpha or pc (little-endian) or sun or sgi (big-endian)");
    }
  }
  header.spacing = {parser.positive_double("VX", 1.0), parser.positive_double("VY", 1.0),
                    parser.positive_double("VZ", 1.0)};
  return header;
}

template <class V> float load(const unsigned char* bytes) {
  V v;
  std::memcpy(&v, bytes, sizeof(V));
  return static_cast<float>(v);
}

/// Sample n of the raw voxel data as float; `swap` reverses the bytes of each sample.
float decode(const char* raw, std::size_t n, Sample sample, bool swap) {
  const std::size_t size = sample_bytes(sample);
  unsigned char b[8];
  std::memcpy(b, raw + n * size, size);
  if (swap) {
    std::reverse(b, b + size);
  }
  switch (sample) {
  case Sample::float32:
    return load<float>(b);
  case Sample::float64:
    return load<double>(b);
  case Sample::uint8:
    return load<std::uint8_t>(b);
  case Sample::uint16:
    return load<std::uint16_t>(b);
  case Sample::uint32:
    return load<std::uint32_t>(b);
  case Sample::int8:
    return load<std::int8_t>(b);
  case Sample::int16:
    return load<std::int16_t>(b);
  case Sample::int32:
    return load<std::int32_t>(b);
  }
  return 0.0f;
}

template <class T> DenseGrid<T> decode_grid(const Header& header, const char* raw, bool swap) {
  DenseGrid<T> grid(header.dims);
  grid.set_spacing(header.spacing);
  std::size_t n = 0;
  for (T& voxel : grid.data()) {
    if constexpr (std::is_same_v<T, float>) {
      voxel = decode(raw, n++, header.sample, swap);
    } else {
      for (int c = 0; c < 3; ++c) {
        voxel[c] = decode(raw, n++, header.sample, swap);
      }
    }
  }
  return grid;
}

} // namespace

AnyGrid read_inr(const std::filesystem::path& path) {
  const std::string bytes = read_regular_file(path, "INRIMAGE volume (.inr)", UINT64_MAX);
  const Header header = parse_header(path, bytes);
  // Checked before the product below is formed: 2^22 x 2^21 x 2^21 voxels would wrap to 0 bytes.
  require_grid_fits(path, header.dims.nx, header.dims.ny, header.dims.nz,
                    static_cast<std::uint64_t>(header.vdim) * sizeof(float));
  const std::size_t expected =
      header.dims.count() * static_cast<std::size_t>(header.vdim) * sample_bytes(header.sample);
  if (bytes.size() - header.bytes < expected) {
    TEXSIM_INPUT_ERROR(path.string()
                       << ": truncated INRIMAGE voxel data, " << bytes.size() - header.bytes
                       << " bytes after the " << header.bytes << "-byte header, expected "
                       << expected << " for " << header.dims.nx << " x " << header.dims.ny << " x "
                       << header.dims.nz << " x " << header.vdim);
  }
  const bool swap = header.big_endian != (std::endian::native == std::endian::big);
  const char* raw = bytes.data() + header.bytes;
  if (header.vdim == 1) {
    return with_finite_voxels(path, decode_grid<float>(header, raw, swap));
  }
  return with_finite_voxels(path, decode_grid<img::Rgb>(header, raw, swap));
}

} // namespace texsim::vol
