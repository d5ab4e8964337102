#include "io/hdf5_scalar_type.hpp"

#include <array>

namespace texsim::io {

hid_t native_hdf5_type(ScalarType type) {
  switch (type) {
  case ScalarType::float64:
    return H5T_NATIVE_DOUBLE;
  case ScalarType::float32:
    return H5T_NATIVE_FLOAT;
  case ScalarType::int32:
    return H5T_NATIVE_INT32;
  case ScalarType::int64:
    return H5T_NATIVE_INT64;
  case ScalarType::uint8:
    return H5T_NATIVE_UINT8;
  case ScalarType::uint64:
    return H5T_NATIVE_UINT64;
  }
  return H5I_INVALID_HID;
}

std::optional<ScalarType> scalar_type_of_hdf5(hid_t type) {
  constexpr std::array all{ScalarType::float64, ScalarType::float32, ScalarType::int32,
                           ScalarType::int64,   ScalarType::uint8,   ScalarType::uint64};
  for (const ScalarType candidate : all)
    if (H5Tequal(type, native_hdf5_type(candidate)) > 0)
      return candidate;
  return std::nullopt;
}

} // namespace texsim::io
