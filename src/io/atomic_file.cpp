#include "io/atomic_file.hpp"

#include "core/error.hpp"

#include <fstream>
#include <system_error>

namespace texsim::io {

void write_file_atomically(const std::filesystem::path& path, std::string_view contents) {
  const auto temporary =
      path.parent_path() / std::string(".").append(path.filename().string()).append(".tmp");
  {
    std::ofstream out(temporary, std::ios::binary | std::ios::trunc);
    out.write(contents.data(), static_cast<std::streamsize>(contents.size()));
    out.close();
    TEXSIM_VERIFY(out, temporary.string() << ": cannot write (directory missing or not writable)");
  }
  std::error_code error;
  std::filesystem::rename(temporary, path, error);
  TEXSIM_VERIFY(!error, "cannot rename " << temporary.string() << " to " << path.string() << ": "
                                         << error.message());
}

} // namespace texsim::io
