#pragma once
/// The most resident memory this process has used so far, for the memory figures a run reports
/// per rank (getrusage's ru_maxrss), and its proportional share now (Linux's PSS: a page that n
/// processes map counts 1/n in each, so memory shared by the ranks of a node counts once).
#include <cstdint>

namespace texsim {

/// Peak resident set size of the calling process in bytes (0 when the system does not say).
std::int64_t peak_resident_bytes();

/// Proportional set size of the calling process now, in bytes, from /proc/self/smaps_rollup
/// (0 when the system does not say).
std::int64_t proportional_resident_bytes();

} // namespace texsim
