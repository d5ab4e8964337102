#pragma once
/// Error types and check macros used by every layer.
///
/// Library code throws and never exits; only main() turns an exception into a message and an exit
/// code: InputError (bad config, missing or malformed file) -> exit 2, any other Error -> exit 1.
#include <sstream>
#include <stdexcept>
#include <string>

namespace texsim {

/// Internal failure: a broken invariant, a failed library call, an I/O error not caused by the
/// user.
class Error : public std::runtime_error {
public:
  using std::runtime_error::runtime_error;

  /// True when every rank holds this same error (thrown by par::run_collectively), so main() can
  /// exit normally; otherwise main() must abort the job to keep the other ranks from hanging.
  bool on_all_ranks() const { return on_all_ranks_; }
  void mark_on_all_ranks() { on_all_ranks_ = true; }

private:
  bool on_all_ranks_ = false;
};

/// The user's input is wrong: the message names the config key path or the file, what was found and
/// what was expected. main() prints it on rank 0 and exits with code 2.
class InputError : public Error {
public:
  using Error::Error;
};

namespace detail {
[[noreturn]] inline void throw_error(const std::string& message, const char* file, int line) {
  std::ostringstream out;
  out << message << " [" << file << ":" << line << "]";
  throw Error(out.str());
}
} // namespace detail
} // namespace texsim

/// Always-on invariant check: TEXSIM_VERIFY(n > 0, "mesh has no vertices, n = " << n);
/// throws texsim::Error carrying file:line.
#define TEXSIM_VERIFY(condition, message_stream)                                                   \
  do {                                                                                             \
    if (!(condition)) {                                                                            \
      std::ostringstream texsim_verify_message_;                                                   \
      texsim_verify_message_ << message_stream;                                                    \
      ::texsim::detail::throw_error(texsim_verify_message_.str(), __FILE__, __LINE__);             \
    }                                                                                              \
  } while (0)

/// Debug-only variant of TEXSIM_VERIFY for checks on hot paths.
#ifndef NDEBUG
#define TEXSIM_ASSERT(condition, message_stream) TEXSIM_VERIFY(condition, message_stream)
#else
#define TEXSIM_ASSERT(condition, message_stream)                                                   \
  do {                                                                                             \
  } while (0)
#endif

/// Throws texsim::InputError with a streamed message: TEXSIM_INPUT_ERROR(path << ": not a mesh");
#define TEXSIM_INPUT_ERROR(message_stream)                                                         \
  do {                                                                                             \
    std::ostringstream texsim_input_message_;                                                      \
    texsim_input_message_ << message_stream;                                                       \
    throw ::texsim::InputError(texsim_input_message_.str());                                       \
  } while (0)
