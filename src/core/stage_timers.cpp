#include "core/stage_timers.hpp"

#include "core/peak_memory.hpp"

#include <algorithm>
#include <chrono>

namespace texsim {

double wall_seconds() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

StageTimers::Scope::Scope(StageTimers& owner, std::size_t index)
    : owner_(owner), index_(index), start_s_(wall_seconds()) {}

StageTimers::Scope::~Scope() {
  auto& stage = owner_.stages_[index_];
  stage.wall_s += wall_seconds() - start_s_;
  ++stage.calls;
  stage.peak_resident_bytes = texsim::peak_resident_bytes();
  if (stage.peak_resident_bytes > owner_.sampled_at_peak_) {
    owner_.sampled_at_peak_ = stage.peak_resident_bytes;
    owner_.largest_proportional_bytes_ =
        std::max(owner_.largest_proportional_bytes_, texsim::proportional_resident_bytes());
  }
}

StageTimers::Scope StageTimers::scope(const std::string& name) {
  for (std::size_t i = 0; i < stages_.size(); ++i)
    if (stages_[i].name == name)
      return Scope(*this, i);
  stages_.push_back({name, 0.0, 0});
  return Scope(*this, stages_.size() - 1);
}

} // namespace texsim
