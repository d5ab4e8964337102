#pragma once
/// What a run reports in summary.json besides timings: quality metrics and output files.
#include <nlohmann/json.hpp>

#include <string>
#include <vector>

namespace texsim {

class RunReport {
public:
  /// Sets metrics[name] (numbers, strings, booleans or nested JSON objects).
  void metric(const std::string& name, nlohmann::json value) { metrics_[name] = std::move(value); }
  /// Records a file the run wrote (path as given, usually inside output.dir).
  void output(const std::string& path);

  const nlohmann::json& metrics() const { return metrics_; }
  const std::vector<std::string>& outputs() const { return outputs_; }

private:
  nlohmann::json metrics_ = nlohmann::json::object();
  std::vector<std::string> outputs_;
};

inline void RunReport::output(const std::string& path) {
  for (const auto& known : outputs_)
    if (known == path)
      return;
  outputs_.push_back(path);
}

} // namespace texsim
