#include "pipelines/fluid_lapped/fluid_lapped_settings.hpp"

#include "core/error.hpp"

namespace texsim::pipelines::fluid_lapped {
namespace {

FrameSourceSettings read_frame_files(const ConfigSection& section) {
  FrameSourceSettings files;
  files.frames = section.require<std::string>("surfaces");
  files.frame_interval = section.get<double>("interval", 1.0, positive());
  files.velocity_grids = section.get<std::string>("velocity_grids", "");
  if (!files.velocity_grids.empty()) {
    if (section.has("velocity_array"))
      section.fail("velocity_array", "no velocity_array with velocity_grids (one velocity source)");
    files.velocity_array.clear();
    files.grid_array = section.get<std::string>("grid_array", files.grid_array);
  } else {
    files.velocity_array = section.get<std::string>("velocity_array", files.velocity_array);
    if (files.velocity_array.empty())
      section.fail("velocity_array", "the name of the surfaces' 3-component velocity point "
                                     "array (OpenFOAM: U), or velocity_grids");
  }
  files.level_set_grid = section.get<std::string>("level_set_grid", files.level_set_grid);
  files.edge_length = section.get<double>("edge_length", 0.0, non_negative());
  return files;
}

FrameSettings read_frames(const ConfigSection& section) {
  FrameSettings frames;
  const bool has_files = section.has("surfaces"), has_flow = section.has("flow");
  if (has_files == has_flow)
    section.fail("surfaces", "exactly one of surfaces (simulator frames: a .pvd or a name "
                             "pattern) and flow (an analytic flow over `mesh`)");
  frames.count = section.get<int>("count", 0, non_negative_int());
  if (has_files) {
    frames.files = read_frame_files(section);
  } else {
    if (frames.count < 1)
      section.fail("count", "the number of frames (>= 1) of the analytic flow");
    frames.mesh = geom::read_mesh_source(section.section("mesh"));
    frames.flow = read_analytic_flow(section.section("flow"));
    frames.interval = section.get<double>("interval", frames.interval, positive());
  }
  return frames;
}

ExemplarSettings read_exemplar(const ConfigSection& section) {
  ExemplarSettings exemplar;
  exemplar.image = section.require<std::string>("image");
  exemplar.feature_map = section.get<std::string>("feature_map", "");
  exemplar.displacement = section.get<std::string>("displacement", "");
  for (const auto& [key, path] :
       {std::pair{"image", exemplar.image}, std::pair{"feature_map", exemplar.feature_map},
        std::pair{"displacement", exemplar.displacement}})
    if (!path.empty() && !std::filesystem::is_regular_file(path))
      section.fail(key, "an existing image file (PNG, JPEG or GIMP .pat)");
  return exemplar;
}

AtlasSettings read_atlas(const ConfigSection& section) {
  AtlasSettings atlas;
  atlas.resolution = section.get<int>("resolution", atlas.resolution, int_in_range(16, 16384));
  atlas.gutter = section.get<int>("gutter", atlas.gutter, int_in_range(0, 16));
  atlas.tile = section.get<int>("tile", atlas.tile, int_in_range(16, 16384));
  atlas.layout = section.choice<AtlasLayout>(
      "layout", atlas.layout, {{"charts", AtlasLayout::charts}, {"planar", AtlasLayout::planar}});
  atlas.max_chart_triangles =
      section.get<int>("max_chart_triangles", atlas.max_chart_triangles, positive_int());
  atlas.max_normal_deviation_degrees = section.get<double>(
      "max_normal_deviation", atlas.max_normal_deviation_degrees, in_range(1.0, 180.0));
  return atlas;
}

} // namespace

FluidLappedSettings read_fluid_lapped_settings(const ConfigSection& section) {
  FluidLappedSettings settings;
  settings.frames = read_frames(section.section("frames"));
  settings.exemplar = read_exemplar(section.section("exemplar"));
  settings.radius = section.require<double>("radius", positive());
  const auto erosion = section.section("erosion");
  settings.delta_max = erosion.get<double>("delta_max", settings.delta_max, [](double d) {
    return d > 1 ? std::string() : std::string("a distortion above 1 (the paper's 3)");
  });
  settings.epsilon = erosion.get<double>("epsilon", settings.epsilon, [](double e) {
    return e > 0 && e < 1 ? std::string() : std::string("a number in ]0, 1[ (the paper's 0.1)");
  });
  settings.atlas = read_atlas(section.section("atlas"));
  settings.creation_batch =
      section.get<int>("creation_batch", settings.creation_batch, int_in_range(1, 65536));
  settings.substep_multiplier =
      section.section("advection")
          .get<int>("substep_multiplier", settings.substep_multiplier, int_in_range(1, 1024));
  return settings;
}

} // namespace texsim::pipelines::fluid_lapped
