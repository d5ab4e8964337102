#pragma once
/// Stable 64-bit hashes for config identity and content checks (not cryptographic).
#include <cstdint>
#include <string>
#include <string_view>

namespace texsim {

/// FNV-1a's starting state.
inline constexpr std::uint64_t kFnv1a64Offset = 0xcbf29ce484222325ULL;

/// FNV-1a over the bytes of `text`, from `state`: fnv1a64(b, fnv1a64(a)) is the hash of a + b,
/// so a long buffer can be hashed after a header without copying them together.
std::uint64_t fnv1a64(std::string_view text, std::uint64_t state = kFnv1a64Offset);

/// 16 lower-case hex digits.
std::string hex64(std::uint64_t value);

} // namespace texsim
