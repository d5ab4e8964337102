#include "io/checkpoint_format.hpp"

#include "core/atomic_output.hpp"

#include <algorithm>
#include <cstdio>

namespace texsim::io {

std::string checkpoint_file_name(std::int64_t step) {
  char name[64];
  std::snprintf(name, sizeof name, "step_%09lld.h5", static_cast<long long>(step));
  return name;
}

std::optional<std::int64_t> checkpoint_step_of(const std::string& file_name) {
  const std::string prefix = "step_";
  const std::string suffix = ".h5";
  if (file_name.size() <= prefix.size() + suffix.size() || !file_name.starts_with(prefix) ||
      !file_name.ends_with(suffix))
    return std::nullopt;
  const std::string digits =
      file_name.substr(prefix.size(), file_name.size() - prefix.size() - suffix.size());
  if (digits.size() > 18 ||
      !std::all_of(digits.begin(), digits.end(), [](char c) { return c >= '0' && c <= '9'; }))
    return std::nullopt;
  return std::stoll(digits);
}

std::vector<std::int64_t> list_checkpoint_steps(const std::filesystem::path& directory) {
  std::vector<std::int64_t> steps;
  std::error_code error;
  for (const auto& entry : std::filesystem::directory_iterator(directory, error))
    if (const auto step = checkpoint_step_of(entry.path().filename().string()))
      steps.push_back(*step);
  std::sort(steps.begin(), steps.end());
  return steps;
}

void remove_uncommitted_checkpoints(const std::filesystem::path& directory) {
  std::error_code error;
  for (const auto& entry : std::filesystem::directory_iterator(directory, error)) {
    const auto final_name = final_name_of_temporary(entry.path().filename().string());
    if (final_name && checkpoint_step_of(*final_name))
      std::filesystem::remove(entry.path(), error);
  }
}

} // namespace texsim::io
