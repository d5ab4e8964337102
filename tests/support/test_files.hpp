#pragma once
/// Hand-made input files for reader tests: bytes assembled field by field and written to disk.
#include <cstdint>
#include <filesystem>
#include <vector>

namespace texsim::test {

/// The raw contents of a file.
using Bytes = std::vector<unsigned char>;

/// Appends `value` as four bytes, most significant first (the order of PNG and GIMP fields).
inline void append_u32_big_endian(Bytes& out, std::uint32_t value) {
  for (int shift = 24; shift >= 0; shift -= 8) {
    out.push_back(static_cast<unsigned char>(value >> shift));
  }
}

/// Writes `bytes` to `path`, replacing any file there, and returns `path`. Not collective.
std::filesystem::path write_bytes(const std::filesystem::path& path, const Bytes& bytes);

} // namespace texsim::test
