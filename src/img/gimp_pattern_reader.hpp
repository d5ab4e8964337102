#pragma once
/// GIMP pattern files (.pat): a big-endian header (header_size, version 1, width, height,
/// bytes per pixel 1-4, magic "GPAT", NUL-terminated UTF-8 name) followed at header_size by
/// width * height * bytes_per_pixel bytes, rows top to bottom.
#include "img/image.hpp"

#include <filesystem>
#include <string>

namespace texsim::img {

/// A pattern's name (from its header) and pixels.
struct GimpPattern {
  std::string name;
  /// Grey (1 or 2 bytes per pixel) replicated into three channels; alpha (2 or 4) dropped; v / 255.
  RgbImage image;
};

/// Reads a .pat file. Throws InputError naming the file and the offending header field (or the
/// missing byte count) if the file is missing, truncated or not a GIMP pattern.
GimpPattern read_gimp_pattern(const std::filesystem::path& path);

} // namespace texsim::img
