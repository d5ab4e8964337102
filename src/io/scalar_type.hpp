#pragma once
/// The element types a checkpoint dataset may hold, named independently of HDF5 so that public
/// headers do not include hdf5.h.
#include <cstddef>
#include <cstdint>
#include <type_traits>

namespace texsim::io {

enum class ScalarType { float64, float32, int32, int64, uint8, uint64 };

template <class T> constexpr ScalarType scalar_type_of() {
  if constexpr (std::is_same_v<T, double>)
    return ScalarType::float64;
  else if constexpr (std::is_same_v<T, float>)
    return ScalarType::float32;
  else if constexpr (std::is_same_v<T, std::int32_t>)
    return ScalarType::int32;
  else if constexpr (std::is_same_v<T, std::int64_t>)
    return ScalarType::int64;
  else if constexpr (std::is_same_v<T, std::uint8_t>)
    return ScalarType::uint8;
  else if constexpr (std::is_same_v<T, std::uint64_t>)
    return ScalarType::uint64;
  else
    static_assert(sizeof(T) == 0, "checkpoint datasets hold double, float, int32, int64, uint8 or "
                                  "uint64 elements");
}

/// Size of one element in bytes.
std::size_t scalar_size(ScalarType type);

/// "float64", "int32", ...: for messages.
const char* scalar_type_name(ScalarType type);

} // namespace texsim::io
