#pragma once
/// Opening a user's data or config file safely: only regular files are read (a FIFO, a device
/// such as /dev/zero or a directory would hang or never end), and names are shortened before they
/// are echoed in messages.
#include <cstdint>
#include <filesystem>
#include <string>

namespace texsim {

/// `text` unchanged when it has at most `max_chars` characters; otherwise its start and end
/// around "...(N characters)...", so a 1 MiB file name does not flood the terminal.
std::string shortened(const std::string& text, std::size_t max_chars = 200);

/// Throws InputError naming `what` (e.g. "mesh file") unless `path` is an existing regular file
/// (symbolic links followed) of at most `max_bytes` bytes. Returns its size in bytes. Serial.
std::uint64_t require_regular_file(const std::filesystem::path& path, const std::string& what,
                                   std::uint64_t max_bytes = UINT64_MAX);

/// The whole content of a regular file of at most `max_bytes` bytes (checked as
/// require_regular_file does before opening it). Throws InputError naming `what`. Serial.
std::string read_regular_file(const std::filesystem::path& path, const std::string& what,
                              std::uint64_t max_bytes);

} // namespace texsim
