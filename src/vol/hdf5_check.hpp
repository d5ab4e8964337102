#pragma once
/// HDF5 return-code discipline for the vol layer: every call goes through TEXSIM_HDF5_CALL, and
/// identifiers are owned by Hdf5Handle so they are closed on every path, exceptions included.
#include "core/error.hpp"

#include <hdf5.h>

#include <mutex>
#include <sstream>
#include <string>
#include <utility>

namespace texsim::vol {
namespace detail {

template <class Result, class Context>
Result check_hdf5(Result result, const char* call, Context&& context, const char* file, int line) {
  if (result < 0) {
    std::ostringstream out;
    out << context() << ": HDF5 call " << call << " failed";
    ::texsim::detail::throw_error(out.str(), file, line);
  }
  return result;
}

} // namespace detail

/// Turns off HDF5's automatic printing of its error stack (once per process); failures are then
/// reported only through return codes and the exceptions TEXSIM_HDF5_CALL throws.
inline void silence_hdf5_error_printing() {
  static std::once_flag once;
  std::call_once(once, [] { H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr); });
}

/// Owns an HDF5 identifier and closes it with the matching H5?close function.
class Hdf5Handle {
public:
  using Closer = herr_t (*)(hid_t);
  Hdf5Handle(hid_t id, Closer close) : id_(id), close_(close) {}
  ~Hdf5Handle() {
    if (id_ >= 0) {
      close_(id_);
    }
  }
  Hdf5Handle(Hdf5Handle&& other) noexcept
      : id_(std::exchange(other.id_, H5I_INVALID_HID)), close_(other.close_) {}
  Hdf5Handle(const Hdf5Handle&) = delete;
  Hdf5Handle& operator=(const Hdf5Handle&) = delete;
  Hdf5Handle& operator=(Hdf5Handle&&) = delete;

  hid_t get() const { return id_; }

private:
  hid_t id_;
  Closer close_;
};

} // namespace texsim::vol

/// Evaluates an HDF5 call returning herr_t/hid_t/htri_t and yields its result; a negative result
/// throws texsim::Error with the streamed context (name the file and object), the call and
/// file:line:
///   hid_t d = TEXSIM_HDF5_CALL(H5Dopen2(f, name, H5P_DEFAULT), path << ": dataset " << name);
#define TEXSIM_HDF5_CALL(call, context_stream)                                                     \
  ::texsim::vol::detail::check_hdf5((call), #call,                                                 \
                                    [&] {                                                          \
                                      std::ostringstream texsim_hdf5_context_;                     \
                                      texsim_hdf5_context_ << context_stream;                      \
                                      return texsim_hdf5_context_.str();                           \
                                    },                                                             \
                                    __FILE__, __LINE__)
