#pragma once
/// Progress lines with rate and ETA for long loops, printed on rank 0 at most every `interval_s`
/// seconds (and once at the end). Not collective: call update() on every rank or only on rank 0.
#include <chrono>
#include <cstdint>
#include <string>

namespace texsim {

class Progress {
public:
  /// `unit` names what is counted ("steps", "voxels") in the rate.
  Progress(std::string label, std::int64_t total, std::string unit = "steps",
           double interval_s = 2.0);

  /// Reports that `done` of `total` items are finished.
  void update(std::int64_t done);

  /// Prints the final line with the total time and mean rate.
  void finish();

  /// The line update() would print now; exposed for tests.
  std::string line(std::int64_t done, double elapsed_s) const;

private:
  using Clock = std::chrono::steady_clock;
  std::string label_;
  std::int64_t total_;
  std::string unit_;
  double interval_s_;
  Clock::time_point start_;
  Clock::time_point last_print_;
  std::int64_t done_ = 0;
  bool finished_ = false;
};

/// "1h02m", "3m05s", "12.3s".
std::string format_duration(double seconds);

} // namespace texsim
