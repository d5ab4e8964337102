#include "pipelines/turk_rd/turk_rd_settings.hpp"

#include "core/error.hpp"
#include "geom/mesh_fields.hpp"
#include "geom/point_expression.hpp"

#include <algorithm>
#include <cmath>
#include <numeric>

namespace texsim::pipelines::turk_rd {
namespace {

geom::SurfaceCellsSettings read_cells(const ConfigSection& cells) {
  geom::SurfaceCellsSettings settings;
  settings.count = cells.get<std::int64_t>("count", settings.count, [](std::int64_t n) {
    return n >= 16 ? std::string() : std::string("at least 16 cells");
  });
  const auto relaxation = cells.section("relaxation");
  auto& r = settings.relaxation;
  r.iterations = relaxation.get<int>("iterations", r.iterations, non_negative_int());
  r.radius_factor = relaxation.get<double>("radius_factor", r.radius_factor, positive());
  r.step = relaxation.get<double>("step", r.step, in_range(0.0, 1.0));
  settings.halo_spacings =
      cells.get<double>("halo_spacings", settings.halo_spacings, in_range(3.0, 100.0));
  return settings;
}

std::size_t species_index(const StageSettings& stage, const ConfigSection& section,
                          const std::string& key) {
  const auto it = std::find(stage.species.begin(), stage.species.end(), key);
  if (it == stage.species.end()) {
    std::string known;
    for (const auto& name : stage.species)
      known += (known.empty() ? "" : ", ") + name;
    section.fail(key, "a species of this stage's model (" + known + ")");
  }
  return std::size_t(it - stage.species.begin());
}

std::vector<InitiatorSettings> read_initiators(const ConfigSection& initiators,
                                               const StageSettings& stage,
                                               const std::vector<std::string>& mesh_fields) {
  std::vector<InitiatorSettings> result;
  for (const std::string& name : initiators.keys()) {
    const ConfigSection entry = initiators.section(name);
    InitiatorSettings initiator;
    initiator.name = name;
    initiator.key_path = entry.path();
    if (entry.has("at") == entry.has("region"))
      entry.fail("at", "exactly one of `at: [x, y, z]` and `region: <expression of x, y, z>`");
    if (entry.has("at")) {
      const auto at = entry.require<std::array<double, 3>>("at");
      initiator.at = geom::Vec3(at[0], at[1], at[2]);
      initiator.radius = entry.get<double>("radius", 0.0, non_negative());
    } else {
      initiator.region = entry.require<std::string>("region");
      geom::PointExpression(initiator.region, mesh_fields, entry.key_path("region"));
    }
    const ConfigSection values = entry.section("set");
    for (const std::string& species : values.keys())
      initiator.values.emplace_back(species_index(stage, values, species),
                                    values.require<double>(species));
    result.push_back(std::move(initiator));
  }
  return result;
}

RenderSettings read_render(const ConfigSection& render) {
  RenderSettings settings;
  settings.colormap = PatternColormap::from_config(render, tan_to_dark_stops());
  if (render.has("range")) {
    const auto range = render.require<std::vector<double>>("range");
    if (range.size() != 2 || !(range[0] < range[1]))
      render.fail("range", "[low, high] with low < high");
    settings.range = std::array<double, 2>{range[0], range[1]};
  }
  settings.radius_spacings =
      render.get<double>("radius", settings.radius_spacings, in_range(0.5, 10.0));
  settings.subdivision_levels =
      render.get<int>("subdivision_levels", settings.subdivision_levels, int_in_range(0, 3));
  settings.bump_scale = render.get<double>("bump", settings.bump_scale, non_negative());
  return settings;
}

} // namespace

std::int64_t TurkRdSettings::total_steps() const {
  return std::accumulate(stages.begin(), stages.end(), std::int64_t{0},
                         [](std::int64_t sum, const StageSettings& s) { return sum + s.steps; });
}

std::vector<std::string> earlier_stage_names(const std::vector<StageSettings>& stages,
                                             std::size_t stage) {
  std::vector<std::string> names;
  for (std::size_t k = 0; k < stage; ++k)
    for (const auto& species : stages[k].species)
      names.push_back(stages[k].name + "_" + species);
  return names;
}

TurkRdSettings read_turk_rd_settings(const ConfigSection& section, std::uint64_t seed) {
  TurkRdSettings settings;
  settings.mesh = geom::read_mesh_source(section.section("mesh"));
  settings.cells = read_cells(section.section("cells"));
  settings.mesh_fields = geom::read_mesh_fields(section, settings.mesh);
  settings.diffusion_scale = section.get<std::string>("diffusion_scale", "1");
  geom::PointExpression(settings.diffusion_scale, settings.mesh_fields,
                        section.key_path("diffusion_scale"));

  if (!section.has("stages") || section.section("stages").keys().empty())
    section.fail("stages", "a mapping of stage names to {model, steps, dt, ...}, run in order");
  const ConfigSection stages = section.section("stages");
  const double stability_safety =
      section.get<double>("stability_safety", StageSettings{}.stability_safety, [](double v) {
        return v > 0 && v <= 1 ? std::string() : std::string("a number in (0, 1]");
      });
  for (const std::string& name : stages.keys()) {
    const ConfigSection entry = stages.section(name);
    StageSettings stage;
    stage.name = name;
    stage.key_path = entry.path();
    stage.model = rd::make_reaction_model(entry.section("model"), seed);
    stage.species = stage.model->species();
    stage.steps = entry.get<std::int64_t>("steps", stage.steps, [](std::int64_t n) {
      return n >= 0 ? std::string() : std::string("a non-negative step count");
    });
    stage.dt = entry.get<double>("dt", stage.dt, positive());
    stage.stability_safety = stability_safety;
    const auto earlier = earlier_stage_names(settings.stages, settings.stages.size());
    for (const auto& field : settings.mesh_fields)
      if (std::find(stage.species.begin(), stage.species.end(), field) != stage.species.end() ||
          std::find(earlier.begin(), earlier.end(), field) != earlier.end())
        section.fail("mesh_fields", "names unlike the species and \"<stage>_<species>\" ('" +
                                        field + "' is both)");
    stage.active = entry.get<std::string>("active", "");
    if (!stage.active.empty()) {
      if (settings.stages.empty())
        entry.fail("active", "no `active` on the first stage (there is no earlier pattern)");
      auto active_names = earlier;
      active_names.insert(active_names.end(), settings.mesh_fields.begin(),
                          settings.mesh_fields.end());
      geom::PointExpression(stage.active, active_names, entry.key_path("active"));
    }
    stage.active_start_initial =
        entry.choice<bool>("active_start", false, {{"carried", false}, {"initial", true}});
    stage.show = entry.get<std::string>("show", stage.species.front());
    auto show_names = stage.species;
    show_names.insert(show_names.end(), earlier.begin(), earlier.end());
    geom::PointExpression(stage.show, show_names, entry.key_path("show"));
    if (entry.has("rings")) {
      const ConfigSection rings = entry.section("rings");
      stage.ring_regions = rings.require<std::string>("regions");
      stage.ring_marks = rings.require<std::string>("marks");
      geom::PointExpression(stage.ring_regions, show_names, rings.key_path("regions"));
      geom::PointExpression(stage.ring_marks, show_names, rings.key_path("marks"));
    }
    if (entry.has("stripes_axis")) {
      const auto axis = entry.require<std::vector<double>>("stripes_axis");
      if (axis.size() != 3 || !(std::hypot(axis[0], axis[1], axis[2]) > 0) ||
          !std::isfinite(std::hypot(axis[0], axis[1], axis[2])))
        entry.fail("stripes_axis", "a nonzero direction [x, y, z]");
      stage.stripes_axis = geom::Vec3(axis[0], axis[1], axis[2]);
    }
    if (entry.has("network")) {
      const ConfigSection network = entry.section("network");
      stage.network_web = network.require<std::string>("web");
      geom::PointExpression(stage.network_web, show_names, network.key_path("web"));
    }
    stage.initiators = read_initiators(entry.section("initiators"), stage, settings.mesh_fields);
    settings.stages.push_back(std::move(stage));
  }
  settings.render = read_render(section.section("render"));
  return settings;
}

} // namespace texsim::pipelines::turk_rd
