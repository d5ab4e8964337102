#include "io/hdf5_call.hpp"

#include <hdf5.h>

namespace texsim::io {

void silence_hdf5_errors() {
  H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
}

} // namespace texsim::io
