#include "app/run_settings.hpp"

#include "app/pipeline_registry.hpp"

namespace texsim::app {

CommonConfig read_common_config(const ConfigSection& root) {
  CommonConfig config;
  config.pipeline = root.require<std::string>("pipeline", [](const std::string& name) {
    return is_registered_pipeline(name) ? "" : "one of " + registered_pipeline_list();
  });
  config.run.seed = root.get<std::uint64_t>("seed", config.run.seed);

  const auto output = root.section("output");
  config.run.output_dir =
      output.get<std::string>("dir", "out/" + config.pipeline, [](const std::string& dir) {
        return dir.empty() ? "a directory name" : "";
      });
  config.run.output_every = output.get<int>("every", config.run.output_every, positive_int());
  config.overwrite_output = output.get<bool>("overwrite", false);

  const auto checkpoint = root.section("checkpoint");
  config.run.checkpoint_every =
      checkpoint.get<int>("every", config.run.checkpoint_every, non_negative_int());
  config.run.checkpoint_keep =
      checkpoint.get<int>("keep", config.run.checkpoint_keep, positive_int());
  if (checkpoint.has("minutes"))
    config.run.checkpoint_minutes = checkpoint.get<double>("minutes", 0.0, non_negative());

  config.petsc = root.string_map("petsc");
  return config;
}

} // namespace texsim::app
