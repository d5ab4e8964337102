#pragma once
/// Comparing what two runs wrote, file by file and byte by byte.
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

namespace texsim::test {

/// Paths of the regular files under `dir`, relative to it, sorted.
std::vector<std::string> files_under(const std::filesystem::path& dir);

/// True when the two files hold the same bytes.
bool same_bytes(const std::filesystem::path& a, const std::filesystem::path& b);

/// The files of `reference` (relative paths, those `compared` accepts) that are missing from
/// `other` or differ from it in any byte. Empty when `other` holds the same bytes.
std::vector<std::string> differing_files(const std::filesystem::path& reference,
                                         const std::filesystem::path& other,
                                         const std::function<bool(const std::string&)>& compared);

} // namespace texsim::test
