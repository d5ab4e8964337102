#pragma once
/// Choosing whether a run may write into output.dir: a directory that holds another run's files is
/// never overwritten by accident, and --restart needs a run to continue.
#include "app/run_settings.hpp"
#include "par/comm.hpp"
#include "pipelines/pipeline.hpp"

#include <filesystem>
#include <string>

namespace texsim::app {

/// The first file in `dir` (or in a folder directly below it) that texsim writes: summary.json,
/// checkpoints/, ParaView files (.pvd .vtp .pvtp .vtu .pvtu .vti), volumes (.vdb .h5) or PNG
/// cross-sections; empty when there is none. Serial.
std::filesystem::path first_run_output(const std::filesystem::path& dir);

/// Creates output.dir. Refuses (InputError on every rank) a directory holding any texsim output
/// unless output.overwrite is set (then its checkpoints are removed) or --restart is given; with
/// --restart, refuses a pipeline that writes no checkpoints, a directory whose summary.json names
/// another pipeline, and a directory without checkpoints (or a checkpoint path that is not a
/// file). Collective.
void prepare_output_dir(const par::Comm& comm, const CommonConfig& common,
                        const pipelines::Pipeline& pipeline);

} // namespace texsim::app
