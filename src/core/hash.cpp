#include "core/hash.hpp"

#include <cstdio>

namespace texsim {

std::uint64_t fnv1a64(std::string_view text, std::uint64_t state) {
  std::uint64_t hash = state;
  for (unsigned char c : text) {
    hash ^= c;
    hash *= 0x100000001b3ULL;
  }
  return hash;
}

std::string hex64(std::uint64_t value) {
  char buffer[17];
  std::snprintf(buffer, sizeof buffer, "%016llx", static_cast<unsigned long long>(value));
  return buffer;
}

} // namespace texsim
