#pragma once
/// Owning wrapper for an HDF5 identifier (file, dataset, dataspace, attribute, property list,
/// type): closes it with the matching H5?close on destruction. Closing a file opened with MPI-IO is
/// collective, so a handle to such a file must be destroyed on every rank.
#include <hdf5.h>

#include <utility>

namespace texsim::par {

class Hdf5Handle {
public:
  using Closer = herr_t (*)(hid_t);

  Hdf5Handle() = default;
  Hdf5Handle(hid_t id, Closer closer) : id_(id), closer_(closer) {}
  Hdf5Handle(const Hdf5Handle&) = delete;
  Hdf5Handle& operator=(const Hdf5Handle&) = delete;
  Hdf5Handle(Hdf5Handle&& other) noexcept
      : id_(std::exchange(other.id_, H5I_INVALID_HID)), closer_(other.closer_) {}
  Hdf5Handle& operator=(Hdf5Handle&& other) noexcept {
    if (this != &other) {
      reset();
      id_ = std::exchange(other.id_, H5I_INVALID_HID);
      closer_ = other.closer_;
    }
    return *this;
  }
  ~Hdf5Handle() { reset(); }

  hid_t get() const { return id_; }
  explicit operator bool() const { return id_ >= 0; }

  /// Closes the identifier now; the return code is returned for callers that must check it
  /// (closing a file flushes it).
  herr_t reset() {
    herr_t status = 0;
    if (id_ >= 0)
      status = closer_(id_);
    id_ = H5I_INVALID_HID;
    return status;
  }

private:
  hid_t id_ = H5I_INVALID_HID;
  Closer closer_ = nullptr;
};

} // namespace texsim::par
