#include "io/scalar_type.hpp"

namespace texsim::io {

std::size_t scalar_size(ScalarType type) {
  switch (type) {
  case ScalarType::float64:
  case ScalarType::int64:
  case ScalarType::uint64:
    return 8;
  case ScalarType::float32:
  case ScalarType::int32:
    return 4;
  case ScalarType::uint8:
    return 1;
  }
  return 0;
}

const char* scalar_type_name(ScalarType type) {
  switch (type) {
  case ScalarType::float64:
    return "float64";
  case ScalarType::float32:
    return "float32";
  case ScalarType::int32:
    return "int32";
  case ScalarType::int64:
    return "int64";
  case ScalarType::uint8:
    return "uint8";
  case ScalarType::uint64:
    return "uint64";
  }
  return "unknown";
}

} // namespace texsim::io
