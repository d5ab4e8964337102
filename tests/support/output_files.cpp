#include "support/output_files.hpp"

#include <algorithm>
#include <cstdio>
#include <fstream>
#include <iterator>
#include <sstream>

namespace texsim::test {
namespace fs = std::filesystem;

std::vector<std::string> files_under(const fs::path& dir) {
  std::vector<std::string> files;
  for (const auto& entry : fs::recursive_directory_iterator(dir))
    if (entry.is_regular_file())
      files.push_back(fs::relative(entry.path(), dir).string());
  std::sort(files.begin(), files.end());
  return files;
}

bool same_bytes(const fs::path& a, const fs::path& b) {
  std::ifstream in_a(a, std::ios::binary), in_b(b, std::ios::binary);
  if (!in_a || !in_b)
    return false;
  return std::equal(std::istreambuf_iterator<char>(in_a), std::istreambuf_iterator<char>(),
                    std::istreambuf_iterator<char>(in_b), std::istreambuf_iterator<char>());
}

std::vector<std::string> differing_files(const fs::path& reference, const fs::path& other,
                                         const std::function<bool(const std::string&)>& compared) {
  std::vector<std::string> differing;
  for (const auto& file : files_under(reference))
    if (compared(file) && !same_bytes(reference / file, other / file))
      differing.push_back(file);
  return differing;
}

std::string read_text(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

nlohmann::json read_summary(const fs::path& out) {
  std::ifstream in(out / "summary.json");
  return nlohmann::json::parse(in);
}

fs::path checkpoint_file(const fs::path& out, std::int64_t step) {
  char name[32];
  std::snprintf(name, sizeof name, "step_%09lld.h5", static_cast<long long>(step));
  return out / "checkpoints" / name;
}

int stage_calls(const nlohmann::json& summary, const std::string& name) {
  for (const auto& stage : summary["stages"])
    if (stage["name"] == name)
      return stage["calls"].get<int>();
  return -1;
}

} // namespace texsim::test
