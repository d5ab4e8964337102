#include "core/peak_memory.hpp"

#include <sys/resource.h>

namespace texsim {

std::int64_t peak_resident_bytes() {
  rusage usage{};
  if (getrusage(RUSAGE_SELF, &usage) != 0)
    return 0;
  return std::int64_t(usage.ru_maxrss) * 1024; // Linux reports kilobytes
}

} // namespace texsim
