#include "core/atomic_output.hpp"

#include "core/error.hpp"

#include <fcntl.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <system_error>

namespace texsim {
namespace {

constexpr std::string_view kTemporaryMarker = ".tmp-";

std::string errno_text(int code) {
  return std::error_code(code, std::generic_category()).message();
}

/// Flushes what the kernel holds for `path` (a file's data or a directory's entries) to the
/// device. A file system that cannot sync that kind of object reports EINVAL; there is nothing
/// more to do then.
void sync_to_disk(const std::filesystem::path& path, bool directory,
                  const std::filesystem::path& named) {
  const int flags = O_RDONLY | O_CLOEXEC | (directory ? O_DIRECTORY : 0);
  const int fd = ::open(path.c_str(), flags);
  TEXSIM_VERIFY(fd >= 0, named.string()
                             << ": cannot open " << (directory ? "its directory " : "")
                             << path.string() << " to flush it to disk: " << errno_text(errno));
  const int synced = ::fsync(fd);
  const int sync_error = errno;
  ::close(fd);
  TEXSIM_VERIFY(synced == 0 || sync_error == EINVAL, named.string()
                                                         << ": cannot flush " << path.string()
                                                         << " to disk: " << errno_text(sync_error));
}

void remove_quietly(const std::filesystem::path& path) {
  std::error_code ignored;
  std::filesystem::remove(path, ignored);
}

/// A new file at `path`, written in parts; errors name `named`.
class FileSink {
public:
  FileSink(const std::filesystem::path& path, const std::filesystem::path& named)
      : named_(named), fd_(::open(path.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0666)) {
    TEXSIM_VERIFY(fd_ >= 0, named.string() << ": cannot create " << path.string() << ": "
                                           << errno_text(errno));
  }
  FileSink(const FileSink&) = delete;
  FileSink& operator=(const FileSink&) = delete;
  ~FileSink() {
    if (fd_ >= 0)
      ::close(fd_);
  }

  void write(std::string_view contents) {
    std::size_t done = 0;
    while (done < contents.size()) {
      const ssize_t written = ::write(fd_, contents.data() + done, contents.size() - done);
      if (written < 0 && errno == EINTR)
        continue;
      TEXSIM_VERIFY(written > 0,
                    named_.string() << ": cannot write: " << errno_text(written < 0 ? errno : EIO));
      done += static_cast<std::size_t>(written);
    }
  }

  void close() {
    const int fd = fd_;
    fd_ = -1;
    TEXSIM_VERIFY(::close(fd) == 0, named_.string() << ": cannot write: " << errno_text(errno));
  }

private:
  std::filesystem::path named_;
  int fd_;
};

} // namespace

std::filesystem::path temporary_path_of(const std::filesystem::path& path, long process_id) {
  std::string name = path.filename().string();
  name += kTemporaryMarker;
  name += std::to_string(process_id);
  return path.parent_path() / name;
}

std::filesystem::path temporary_path_of(const std::filesystem::path& path) {
  return temporary_path_of(path, static_cast<long>(::getpid()));
}

std::optional<std::string> final_name_of_temporary(const std::string& file_name) {
  const auto marker = file_name.rfind(kTemporaryMarker);
  if (marker == std::string::npos || marker == 0)
    return std::nullopt;
  const auto digits = std::string_view(file_name).substr(marker + kTemporaryMarker.size());
  if (digits.empty() ||
      !std::all_of(digits.begin(), digits.end(), [](char c) { return c >= '0' && c <= '9'; }))
    return std::nullopt;
  return file_name.substr(0, marker);
}

void commit_temporary(const std::filesystem::path& temporary, const std::filesystem::path& path) {
  try {
    sync_to_disk(temporary, false, path);
    std::error_code error;
    std::filesystem::rename(temporary, path, error);
    TEXSIM_VERIFY(!error, path.string() << ": cannot rename " << temporary.string()
                                        << " to it: " << error.message());
  } catch (...) {
    remove_quietly(temporary);
    throw;
  }
  const auto directory =
      path.parent_path().empty() ? std::filesystem::path(".") : path.parent_path();
  sync_to_disk(directory, true, path);
}

void write_atomically(const std::filesystem::path& path,
                      const std::function<void(const std::filesystem::path&)>& write) {
  const auto temporary = temporary_path_of(path);
  try {
    write(temporary);
  } catch (...) {
    remove_quietly(temporary);
    throw;
  }
  commit_temporary(temporary, path);
}

void write_atomically(const std::filesystem::path& path, std::string_view contents) {
  write_atomically_in_parts(path, [&](const TextSink& emit) { emit(contents); });
}

void write_atomically_in_parts(const std::filesystem::path& path,
                               const std::function<void(const TextSink& emit)>& produce) {
  write_atomically(path, [&](const std::filesystem::path& temporary) {
    FileSink file(temporary, path);
    produce([&](std::string_view part) { file.write(part); });
    file.close();
  });
}

} // namespace texsim
