#pragma once
/// The most resident memory this process has used so far, for the memory figures a run reports
/// per rank (getrusage's ru_maxrss).
#include <cstdint>

namespace texsim {

/// Peak resident set size of the calling process in bytes (0 when the system does not say).
std::int64_t peak_resident_bytes();

} // namespace texsim
