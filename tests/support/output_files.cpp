#include "support/output_files.hpp"

#include <algorithm>
#include <fstream>
#include <iterator>

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

} // namespace texsim::test
