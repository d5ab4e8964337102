#include "core/progress.hpp"

#include "core/log.hpp"

#include <cmath>
#include <cstdio>

namespace texsim {

std::string format_duration(double seconds) {
  char buffer[32];
  if (!std::isfinite(seconds) || seconds < 0)
    return "?";
  if (seconds < 60)
    std::snprintf(buffer, sizeof buffer, "%.1fs", seconds);
  else if (seconds < 3600)
    std::snprintf(buffer, sizeof buffer, "%dm%02ds", int(seconds) / 60, int(seconds) % 60);
  else
    std::snprintf(buffer, sizeof buffer, "%dh%02dm", int(seconds) / 3600, int(seconds) % 3600 / 60);
  return buffer;
}

Progress::Progress(std::string label, std::int64_t total, std::string unit, double interval_s)
    : label_(std::move(label)), total_(total), unit_(std::move(unit)), interval_s_(interval_s),
      start_(Clock::now()), last_print_(start_) {}

std::string Progress::line(std::int64_t done, double elapsed_s) const {
  const double rate = elapsed_s > 0 ? done / elapsed_s : 0.0;
  const double percent = total_ > 0 ? 100.0 * done / total_ : 100.0;
  const double eta = rate > 0 ? (total_ - done) / rate : -1.0;
  char buffer[256];
  std::snprintf(buffer, sizeof buffer, "%s: %lld/%lld (%.0f%%) %.3g %s/s, elapsed %s, ETA %s",
                label_.c_str(), static_cast<long long>(done), static_cast<long long>(total_),
                percent, rate, unit_.c_str(), format_duration(elapsed_s).c_str(),
                format_duration(eta).c_str());
  return buffer;
}

void Progress::update(std::int64_t done) {
  done_ = done;
  const auto now = Clock::now();
  if (std::chrono::duration<double>(now - last_print_).count() < interval_s_)
    return;
  last_print_ = now;
  log::info(line(done, std::chrono::duration<double>(now - start_).count()));
}

void Progress::finish() {
  if (finished_)
    return;
  finished_ = true;
  const double elapsed = std::chrono::duration<double>(Clock::now() - start_).count();
  const double rate = elapsed > 0 ? done_ / elapsed : 0.0;
  char buffer[256];
  std::snprintf(buffer, sizeof buffer, "%s: done, %lld %s in %s (%.3g %s/s)", label_.c_str(),
                static_cast<long long>(done_), unit_.c_str(), format_duration(elapsed).c_str(),
                rate, unit_.c_str());
  log::info(buffer);
}

} // namespace texsim
