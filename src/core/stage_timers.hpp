#pragma once
/// Per-stage wall-clock timers for the run summary: { auto s = timers.scope("assembly"); ... }.
/// A stage entered several times accumulates. Local to the calling rank (no communication).
#include <cstdint>
#include <string>
#include <vector>

namespace texsim {

struct StageTime {
  std::string name;
  double wall_s = 0;
  int calls = 0;
  /// This process's peak resident memory when the stage last ended: the stage where it first
  /// reaches the run's peak is the one that sets it.
  std::int64_t peak_resident_bytes = 0;
};

class StageTimers {
public:
  class Scope {
  public:
    Scope(StageTimers& owner, std::size_t index);
    ~Scope();
    Scope(const Scope&) = delete;
    Scope& operator=(const Scope&) = delete;

  private:
    StageTimers& owner_;
    std::size_t index_;
    double start_s_;
  };

  /// Times the enclosing block as stage `name` (in first-use order in the summary).
  [[nodiscard]] Scope scope(const std::string& name);

  const std::vector<StageTime>& stages() const { return stages_; }
  /// The largest proportional set size (PSS, core/peak_memory.hpp) seen at a stage end. It is
  /// sampled only where the peak resident memory grew since the last sample, which bounds the
  /// cost of reading it and catches the stages that raise memory.
  std::int64_t largest_proportional_bytes() const { return largest_proportional_bytes_; }

private:
  std::vector<StageTime> stages_;
  std::int64_t sampled_at_peak_ = -1;
  std::int64_t largest_proportional_bytes_ = 0;
};

/// Seconds on a monotonic clock.
double wall_seconds();

} // namespace texsim
