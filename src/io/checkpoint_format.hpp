#pragma once
/// What a texsim checkpoint file looks like on disk: its name, the attributes every checkpoint
/// carries, and the format version this build writes and reads.
///
/// <dir>/step_000000100.h5 (written as <dir>/step_000000100.h5.tmp-<pid of rank 0>, flushed and
/// renamed when complete, see core/atomic_output.hpp) holds
/// one dataset per named array at the root, shape {count} or {count, components}, each with a
/// "texsim_checksum" attribute (see par/positional_checksum.hpp), and root attributes
/// "texsim_format_version", "texsim_config_hash", "texsim_step" plus the caller's own.
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace texsim::io {

/// Bumped whenever the layout above changes; a checkpoint of another version is refused.
inline constexpr std::int64_t checkpoint_format_version = 1;

inline constexpr const char* format_version_attribute = "texsim_format_version";
inline constexpr const char* config_hash_attribute = "texsim_config_hash";
inline constexpr const char* step_attribute = "texsim_step";
inline constexpr const char* checksum_attribute = "texsim_checksum";

/// "step_000000100.h5".
std::string checkpoint_file_name(std::int64_t step);

/// The step of a committed checkpoint's file name, or nothing for any other name.
std::optional<std::int64_t> checkpoint_step_of(const std::string& file_name);

/// Steps of the committed checkpoints in `directory`, ascending (empty if it does not exist).
/// Not collective: reads the directory on the calling rank.
std::vector<std::int64_t> list_checkpoint_steps(const std::filesystem::path& directory);

/// Removes the temporary files of checkpoints that were never committed (a job killed while
/// writing one) from `directory`. Not collective: call on one rank, while no checkpoint is being
/// written there.
void remove_uncommitted_checkpoints(const std::filesystem::path& directory);

} // namespace texsim::io
