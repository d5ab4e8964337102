#pragma once
/// Checking every HDF5 return code:
///   hid_t d = TEXSIM_HDF5_CALL(H5Dopen2(f, name, H5P_DEFAULT), path.string() << ": dataset " <<
///   name);
/// evaluates the call and yields its result; a negative result (herr_t, hid_t, htri_t, hssize_t
/// failure) throws texsim::Error carrying the streamed context (name the file and object), the
/// call and file:line. The context is only formatted on failure.
#include "core/error.hpp"

#include <sstream>
#include <string>

namespace texsim::par {

/// Turns off HDF5's automatic printing of its error stack to stderr (library code never prints):
/// failures then reach the caller only through return codes and TEXSIM_HDF5_CALL's exceptions.
/// Idempotent, thread-safe; not collective.
void silence_hdf5_error_printing();

namespace detail {
template <class Result, class Context>
Result check_hdf5(Result result, const char* call, Context&& context, const char* source,
                  int line) {
  if (result < 0) {
    std::ostringstream message;
    message << context() << ": HDF5 call " << call << " failed";
    ::texsim::detail::throw_error(message.str(), source, line);
  }
  return result;
}
} // namespace detail
} // namespace texsim::par

#define TEXSIM_HDF5_CALL(call, context_stream)                                                     \
  ::texsim::par::detail::check_hdf5((call), #call,                                                 \
                                    [&] {                                                          \
                                      std::ostringstream texsim_hdf5_context_;                     \
                                      texsim_hdf5_context_ << context_stream;                      \
                                      return texsim_hdf5_context_.str();                           \
                                    },                                                             \
                                    __FILE__, __LINE__)
