#include "core/peak_memory.hpp"

#include <sys/resource.h>

#include <fstream>
#include <string>

namespace texsim {

std::int64_t peak_resident_bytes() {
  rusage usage{};
  if (getrusage(RUSAGE_SELF, &usage) != 0)
    return 0;
  return std::int64_t(usage.ru_maxrss) * 1024; // Linux reports kilobytes
}

std::int64_t proportional_resident_bytes() {
  std::ifstream rollup("/proc/self/smaps_rollup");
  std::string key;
  std::int64_t kilobytes = 0;
  while (rollup >> key) {
    if (key == "Pss:" && rollup >> kilobytes)
      return kilobytes * 1024;
    rollup.ignore(1 << 20, '\n');
  }
  return 0;
}

} // namespace texsim
