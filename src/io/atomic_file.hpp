#pragma once
/// Replacing a small text file atomically, so a reader (ParaView opening a running job's .pvd)
/// sees either the old or the new contents, never a half-written file.
#include <filesystem>
#include <string_view>

namespace texsim::io {

/// Writes `contents` to a hidden temporary file next to `path` (".<name>.tmp"), then renames it
/// over `path`. Throws texsim::Error naming the file if it cannot be written. Not collective.
void write_file_atomically(const std::filesystem::path& path, std::string_view contents);

} // namespace texsim::io
