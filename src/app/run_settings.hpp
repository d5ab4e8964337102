#pragma once
/// The keys every config has: pipeline, seed, output, checkpoint, petsc.
#include "core/config.hpp"
#include "pipelines/pipeline.hpp"

#include <map>
#include <string>

namespace texsim::app {

struct CommonConfig {
  std::string pipeline;                     ///< pipeline: registry name
  pipelines::RunSettings run;               ///< seed, output.*, checkpoint.*
  bool overwrite_output = false;            ///< output.overwrite
  std::map<std::string, std::string> petsc; ///< petsc: option name (no dash) -> value
};

/// Reads the common keys; the pipeline name is checked against the registry.
CommonConfig read_common_config(const ConfigSection& root);

} // namespace texsim::app
