#include "app/summary_writer.hpp"

#include "core/atomic_output.hpp"
#include "texsim/version.hpp"

#include <algorithm>

namespace texsim::app {

void write_summary(const std::filesystem::path& output_dir, const SummaryHeader& header,
                   const StageTimers& timers, const RunReport& report) {
  nlohmann::json summary;
  summary["pipeline"] = header.pipeline;
  summary["ranks"] = header.ranks;
  summary["threads"] = header.threads;
  summary["wall_s"] = header.wall_s;
  summary["restarted"] = header.restarted;
  summary["texsim_version"] = std::string(build_info::kVersion) + "+" + build_info::kGitHash;
  summary["config_hash"] = header.config_hash;
  summary["stages"] = nlohmann::json::array();
  for (const auto& stage : timers.stages())
    summary["stages"].push_back({{"name", stage.name},
                                 {"wall_s", stage.wall_s},
                                 {"calls", stage.calls},
                                 {"peak_resident_bytes", stage.peak_resident_bytes}});
  if (!header.peak_resident_bytes.empty())
    summary["memory"] = {
        {"peak_resident_bytes_per_rank", header.peak_resident_bytes},
        {"peak_resident_bytes_max",
         *std::max_element(header.peak_resident_bytes.begin(), header.peak_resident_bytes.end())},
        {"proportional_bytes_per_rank", header.proportional_bytes},
        {"proportional_bytes_max",
         *std::max_element(header.proportional_bytes.begin(), header.proportional_bytes.end())}};
  summary["metrics"] = report.metrics();
  summary["outputs"] = report.outputs();

  write_atomically(output_dir / "summary.json", summary.dump(2) + "\n");
}

} // namespace texsim::app
