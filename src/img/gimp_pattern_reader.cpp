#include "img/gimp_pattern_reader.hpp"

#include <algorithm>
#include <cstdint>
#include <fstream>
#include <iterator>
#include <vector>

namespace texsim::img {
namespace {

constexpr std::size_t kFixedHeaderBytes = 24; // six big-endian u32 words

std::uint32_t big_endian_u32(const std::vector<unsigned char>& bytes, std::size_t offset) {
  return (std::uint32_t{bytes[offset]} << 24) | (std::uint32_t{bytes[offset + 1]} << 16) |
         (std::uint32_t{bytes[offset + 2]} << 8) | std::uint32_t{bytes[offset + 3]};
}

} // namespace

GimpPattern read_gimp_pattern(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) {
    TEXSIM_INPUT_ERROR(path.string() << ": GIMP pattern file not found or not readable");
  }
  const std::vector<unsigned char> bytes((std::istreambuf_iterator<char>(in)),
                                         std::istreambuf_iterator<char>());
  if (bytes.size() < kFixedHeaderBytes) {
    TEXSIM_INPUT_ERROR(path.string()
                       << ": " << bytes.size() << " bytes, too short for a GIMP pattern header ("
                       << kFixedHeaderBytes << " bytes at least)");
  }
  const std::uint32_t header_size = big_endian_u32(bytes, 0);
  const std::uint32_t version = big_endian_u32(bytes, 4);
  const std::uint32_t width = big_endian_u32(bytes, 8);
  const std::uint32_t height = big_endian_u32(bytes, 12);
  const std::uint32_t bytes_per_pixel = big_endian_u32(bytes, 16);
  const std::string magic(bytes.begin() + 20, bytes.begin() + 24);
  if (magic != "GPAT") {
    TEXSIM_INPUT_ERROR(path.string()
                       << ": magic is '" << magic << "', expected 'GPAT' (not a GIMP pattern)");
  }
  if (version != 1) {
    TEXSIM_INPUT_ERROR(path.string() << ": version " << version << ", expected 1");
  }
  if (header_size <= kFixedHeaderBytes || header_size > bytes.size()) {
    TEXSIM_INPUT_ERROR(path.string()
                       << ": header_size " << header_size << ", expected " << kFixedHeaderBytes + 1
                       << " to the file size " << bytes.size());
  }
  constexpr std::uint32_t kMaxSide = 1u << 15;
  if (width == 0 || height == 0 || width > kMaxSide || height > kMaxSide) {
    TEXSIM_INPUT_ERROR(path.string() << ": width x height " << width << " x " << height
                                     << ", expected 1 to " << kMaxSide << " each");
  }
  if (bytes_per_pixel < 1 || bytes_per_pixel > 4) {
    TEXSIM_INPUT_ERROR(path.string()
                       << ": bytes per pixel " << bytes_per_pixel << ", expected 1 to 4");
  }
  const std::size_t pixel_bytes = std::size_t{width} * height * bytes_per_pixel;
  if (bytes.size() - header_size < pixel_bytes) {
    TEXSIM_INPUT_ERROR(path.string() << ": truncated pixel data, " << bytes.size() - header_size
                                     << " bytes after the header, expected " << pixel_bytes);
  }

  GimpPattern pattern;
  const auto name_begin = bytes.begin() + kFixedHeaderBytes;
  const auto name_end = bytes.begin() + header_size;
  pattern.name.assign(name_begin, std::find(name_begin, name_end, '\0'));
  pattern.image = RgbImage(static_cast<int>(width), static_cast<int>(height));
  const bool grey = bytes_per_pixel <= 2;
  std::size_t offset = header_size;
  for (Rgb& pixel : pattern.image.data()) {
    for (int c = 0; c < 3; ++c) {
      pixel[c] = static_cast<float>(bytes[offset + (grey ? 0 : c)]) / 255.0f;
    }
    offset += bytes_per_pixel;
  }
  return pattern;
}

} // namespace texsim::img
