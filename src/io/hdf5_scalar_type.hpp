#pragma once
/// Mapping between ScalarType and HDF5's native types.
#include "io/scalar_type.hpp"

#include <hdf5.h>

#include <optional>

namespace texsim::io {

/// The native HDF5 type of `type` (owned by HDF5, do not close).
hid_t native_hdf5_type(ScalarType type);

/// The ScalarType whose native HDF5 type equals `type`, or nothing when the dataset holds
/// something else.
std::optional<ScalarType> scalar_type_of_hdf5(hid_t type);

} // namespace texsim::io
