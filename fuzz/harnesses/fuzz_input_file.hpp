#pragma once
/// The fuzz input as a file: texsim's readers take paths, so every harness writes the bytes to a
/// per-process file with the format's extension and reads it back.
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <unistd.h>

namespace texsim::fuzz {

inline std::filesystem::path write_input(const std::uint8_t* data, std::size_t size,
                                         const std::string& extension) {
  static const std::filesystem::path path =
      std::filesystem::temp_directory_path() /
      ("texsim_fuzz_" + std::to_string(::getpid()) + extension);
  std::ofstream(path, std::ios::binary | std::ios::trunc)
      .write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
  return path;
}

/// Readers refuse volumes and meshes larger than this instead of allocating them, as they refuse
/// what exceeds a node's memory (libFuzzer stops at 2 GiB of RSS).
inline void limit_memory() {
  setenv("TEXSIM_MEMORY_LIMIT", "256M", 1);
}

} // namespace texsim::fuzz
