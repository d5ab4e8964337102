#pragma once
/// Comparing what two runs wrote, file by file and byte by byte, and reading what one run wrote.
#include <nlohmann/json.hpp>

#include <cstdint>
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

/// A file's whole content.
std::string read_text(const std::filesystem::path& path);

/// <out>/summary.json, parsed.
nlohmann::json read_summary(const std::filesystem::path& out);

/// <out>/checkpoints/step_<step>.h5, as io::CheckpointStore names it.
std::filesystem::path checkpoint_file(const std::filesystem::path& out, std::int64_t step);

/// How often a run entered its stage `name` (summary.json "stages"), or -1 if it never did.
int stage_calls(const nlohmann::json& summary, const std::string& name);

} // namespace texsim::test
