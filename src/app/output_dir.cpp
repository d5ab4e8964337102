#include "app/output_dir.hpp"

#include "core/error.hpp"
#include "core/input_file.hpp"
#include "par/collective.hpp"

#include <nlohmann/json.hpp>

#include <array>
#include <fstream>
#include <string_view>

namespace texsim::app {
namespace fs = std::filesystem;
namespace {

bool is_run_output(const fs::directory_entry& entry) {
  static constexpr std::array<std::string_view, 9> kExtensions = {
      ".pvd", ".vtp", ".pvtp", ".vtu", ".pvtu", ".vti", ".vdb", ".h5", ".png"};
  const auto name = entry.path().filename().string();
  // A run refused before its first checkpoint (bad input found while running) leaves checkpoints/
  // empty: nothing to restart from or to lose, so the corrected config may run there.
  if (name == "checkpoints") {
    std::error_code error;
    return !fs::is_empty(entry.path(), error) || error;
  }
  // A write cut short leaves its temporary file (io/atomic_file: NAME.tmp-PID).
  if (name == "summary.json" || name.find(".tmp-") != std::string::npos)
    return true;
  const auto ext = entry.path().extension().string();
  for (const auto known : kExtensions)
    if (ext == known)
      return true;
  return false;
}

/// The pipeline a finished run's summary.json names, or empty.
std::string summary_pipeline(const fs::path& dir) {
  std::ifstream in(dir / "summary.json");
  if (!in)
    return {};
  const auto summary = nlohmann::json::parse(in, nullptr, false);
  if (summary.is_discarded() || !summary.is_object() || !summary.contains("pipeline") ||
      !summary["pipeline"].is_string())
    return {};
  return summary["pipeline"].get<std::string>();
}

void check_restart(const CommonConfig& common, const pipelines::Pipeline& pipeline) {
  const auto& dir = common.run.output_dir;
  const std::string shown = shortened(dir.string());
  if (!pipeline.restartable())
    TEXSIM_INPUT_ERROR("--restart: the " << common.pipeline
                                         << " pipeline writes no checkpoints, so there is nothing "
                                            "to restart; run it without --restart");
  const std::string other = summary_pipeline(dir);
  if (!other.empty() && other != common.pipeline)
    TEXSIM_INPUT_ERROR("--restart: output.dir '" << shown << "' holds a " << other
                                                 << " run (summary.json), not a " << common.pipeline
                                                 << " run");
  const std::string& spec = *common.run.restart;
  if (spec == "latest") {
    if (!fs::is_directory(dir / "checkpoints"))
      TEXSIM_INPUT_ERROR("--restart: output.dir '"
                         << shown
                         << "' holds no checkpoints/ to restart from; run without --restart "
                            "to start afresh (with checkpoint.every > 0 to write checkpoints)");
    return;
  }
  require_regular_file(spec, "checkpoint file (.h5) for --restart");
}

} // namespace

fs::path first_run_output(const fs::path& dir) {
  std::error_code error;
  for (const auto& entry : fs::directory_iterator(dir, error)) {
    if (is_run_output(entry))
      return entry.path();
    if (!entry.is_directory(error))
      continue;
    for (const auto& inner : fs::directory_iterator(entry.path(), error))
      if (is_run_output(inner))
        return inner.path();
  }
  return {};
}

void prepare_output_dir(const par::Comm& comm, const CommonConfig& common,
                        const pipelines::Pipeline& pipeline) {
  par::run_collectively(comm, [&] {
    if (!comm.is_root())
      return;
    const auto& dir = common.run.output_dir;
    const std::string shown = shortened(dir.string());
    std::error_code error;
    if (fs::exists(dir, error) && !fs::is_directory(dir, error))
      TEXSIM_INPUT_ERROR("output.dir: '" << shown << "' exists and is not a directory");
    if (common.run.restart) {
      check_restart(common, pipeline);
      return;
    }
    const fs::path found = first_run_output(dir);
    if (!found.empty() && !common.overwrite_output)
      TEXSIM_INPUT_ERROR("output.dir: '"
                         << shown << "' already holds a run ('" << shortened(found.string())
                         << "'); choose another directory, continue it with --restart, or set "
                            "output.overwrite: true");
    // Overwriting a run starts it afresh: its checkpoints must not be restarted from or mixed in.
    if (!found.empty())
      fs::remove_all(dir / "checkpoints", error);
    fs::create_directories(dir, error);
    if (error)
      TEXSIM_INPUT_ERROR("output.dir: cannot create '" << shown << "': " << error.message());
  });
}

} // namespace texsim::app
