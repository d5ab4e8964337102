#pragma once
/// The pipelines texsim knows, by the name a config gives in `pipeline:`.
#include "pipelines/pipeline.hpp"

#include <memory>
#include <string>
#include <vector>

namespace texsim::app {

/// Registered names in a stable order.
std::vector<std::string> registered_pipelines();
bool is_registered_pipeline(const std::string& name);
/// "a, b, c" for messages.
std::string registered_pipeline_list();

/// A fresh pipeline object; the name must be registered.
std::unique_ptr<pipelines::Pipeline> make_pipeline(const std::string& name);

} // namespace texsim::app
