#include "core/input_file.hpp"

#include "core/error.hpp"

#include <fstream>
#include <system_error>

namespace texsim {

std::string shortened(const std::string& text, std::size_t max_chars) {
  if (text.size() <= max_chars)
    return text;
  const std::size_t head = max_chars * 2 / 3;
  const std::size_t tail = max_chars - head;
  return text.substr(0, head) + "...(" + std::to_string(text.size()) + " characters)..." +
         text.substr(text.size() - tail);
}

std::uint64_t require_regular_file(const std::filesystem::path& path, const std::string& what,
                                   std::uint64_t max_bytes) {
  std::error_code error;
  const auto status = std::filesystem::status(path, error);
  const std::string name = shortened(path.string());
  if (!std::filesystem::exists(status)) {
    const bool plain_missing = !error || error == std::errc::no_such_file_or_directory;
    TEXSIM_INPUT_ERROR(name << ": no such file"
                            << (plain_missing ? "" : " (" + error.message() + ")")
                            << "; expected a " << what);
  }
  if (std::filesystem::is_directory(status))
    TEXSIM_INPUT_ERROR(name << ": is a directory; expected a " << what);
  if (!std::filesystem::is_regular_file(status))
    TEXSIM_INPUT_ERROR(name << ": not a regular file (a FIFO, socket or device); expected a "
                            << what);
  const std::uint64_t size = std::filesystem::file_size(path, error);
  if (error)
    TEXSIM_INPUT_ERROR(name << ": cannot read its size (" << error.message() << "); expected a "
                            << what);
  if (size > max_bytes)
    TEXSIM_INPUT_ERROR(name << ": " << size << " bytes; expected a " << what << " of at most "
                            << max_bytes << " bytes");
  return size;
}

std::string read_regular_file(const std::filesystem::path& path, const std::string& what,
                              std::uint64_t max_bytes) {
  const std::uint64_t size = require_regular_file(path, what, max_bytes);
  std::ifstream in(path, std::ios::binary);
  if (!in)
    TEXSIM_INPUT_ERROR(shortened(path.string())
                       << ": cannot open (unreadable); expected a " << what);
  // Reads the size found above and no more, so a file that keeps growing cannot run away.
  std::string text(size, '\0');
  in.read(text.data(), static_cast<std::streamsize>(size));
  text.resize(static_cast<std::size_t>(in.gcount()));
  return text;
}

} // namespace texsim
