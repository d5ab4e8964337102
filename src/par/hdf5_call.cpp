#include "par/hdf5_call.hpp"

#include <hdf5.h>

#include <mutex>

namespace texsim::par {

void silence_hdf5_error_printing() {
  static std::once_flag once;
  std::call_once(once, [] { H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr); });
}

} // namespace texsim::par
