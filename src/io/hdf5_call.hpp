#pragma once
/// Checking every HDF5 return code: TEXSIM_HDF5_CALL(H5Fclose(file), path) evaluates the call and
/// throws texsim::Error naming the call and the file when it returns a negative value (herr_t or
/// hid_t failure). HDF5's own error printing is silenced by silence_hdf5_errors().
#include "core/error.hpp"

#include <filesystem>
#include <string>

namespace texsim::io {

/// Turns off HDF5's automatic printing of its error stack to stderr (library code never prints).
/// Idempotent; not collective.
void silence_hdf5_errors();

namespace detail {
template <class Result>
Result check_hdf5(Result result, const char* call, const std::filesystem::path& file,
                  const char* source, int line) {
  if (result < 0) {
    std::ostringstream message;
    message << file.string() << ": HDF5 call " << call << " failed";
    ::texsim::detail::throw_error(message.str(), source, line);
  }
  return result;
}
} // namespace detail
} // namespace texsim::io

#define TEXSIM_HDF5_CALL(call, file)                                                               \
  ::texsim::io::detail::check_hdf5((call), #call, (file), __FILE__, __LINE__)
