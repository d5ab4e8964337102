#include "app/pipeline_registry.hpp"

#include "core/error.hpp"
#include "pipelines/fem_rd/fem_rd_pipeline.hpp"
#include "pipelines/fluid_lapped/fluid_lapped_pipeline.hpp"
#include "pipelines/mesh_prep/mesh_prep_pipeline.hpp"
#include "pipelines/solid_synthesis/solid_synthesis_pipeline.hpp"
#include "pipelines/surface_synthesis/surface_synthesis_pipeline.hpp"
#include "pipelines/turk_rd/turk_rd_pipeline.hpp"

#include <functional>
#include <utility>

namespace texsim::app {
namespace {
using Factory = std::function<std::unique_ptr<pipelines::Pipeline>()>;

const std::vector<std::pair<std::string, Factory>>& registry() {
  static const std::vector<std::pair<std::string, Factory>> entries = {
      {"fem_rd", [] { return std::make_unique<pipelines::fem_rd::FemRdPipeline>(); }},
      {"fluid_lapped",
       [] { return std::make_unique<pipelines::fluid_lapped::FluidLappedPipeline>(); }},
      {"mesh_prep", [] { return std::make_unique<pipelines::mesh_prep::MeshPrepPipeline>(); }},
      {"solid_synthesis",
       [] { return std::make_unique<pipelines::solid_synthesis::SolidSynthesisPipeline>(); }},
      {"surface_synthesis",
       [] { return std::make_unique<pipelines::surface_synthesis::SurfaceSynthesisPipeline>(); }},
      {"turk_rd", [] { return std::make_unique<pipelines::turk_rd::TurkRdPipeline>(); }},
  };
  return entries;
}
} // namespace

std::vector<std::string> registered_pipelines() {
  std::vector<std::string> names;
  for (const auto& [name, factory] : registry())
    names.push_back(name);
  return names;
}

bool is_registered_pipeline(const std::string& name) {
  for (const auto& [known, factory] : registry())
    if (known == name)
      return true;
  return false;
}

std::string registered_pipeline_list() {
  std::string list;
  for (const auto& name : registered_pipelines())
    list += (list.empty() ? "" : ", ") + name;
  return list;
}

std::unique_ptr<pipelines::Pipeline> make_pipeline(const std::string& name) {
  for (const auto& [known, factory] : registry())
    if (known == name)
      return factory();
  TEXSIM_VERIFY(false, "pipeline '" << name << "' is not registered");
}

} // namespace texsim::app
