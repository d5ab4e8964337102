#pragma once
/// Stable 64-bit hashes for config identity and content checks (not cryptographic).
#include <cstdint>
#include <string>
#include <string_view>

namespace texsim {

/// FNV-1a over the bytes of `text`.
std::uint64_t fnv1a64(std::string_view text);

/// 16 lower-case hex digits.
std::string hex64(std::uint64_t value);

} // namespace texsim
