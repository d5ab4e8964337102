#include "app/summary_writer.hpp"

#include "core/error.hpp"
#include "texsim/version.hpp"

#include <fstream>

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
    summary["stages"].push_back(
        {{"name", stage.name}, {"wall_s", stage.wall_s}, {"calls", stage.calls}});
  summary["metrics"] = report.metrics();
  summary["outputs"] = report.outputs();

  const auto path = output_dir / "summary.json";
  const auto temporary = output_dir / ".summary.json.tmp";
  {
    std::ofstream out(temporary);
    out << summary.dump(2) << "\n";
    TEXSIM_VERIFY(out.good(), "cannot write " << temporary);
  }
  std::filesystem::rename(temporary, path);
}

} // namespace texsim::app
