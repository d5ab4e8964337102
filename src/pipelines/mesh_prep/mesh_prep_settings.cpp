#include "pipelines/mesh_prep/mesh_prep_settings.hpp"

#include <filesystem>

namespace texsim::pipelines::mesh_prep {

MeshPrepSettings read_mesh_prep_settings(const ConfigSection& section) {
  MeshPrepSettings settings;
  const auto input = section.section("input");
  const bool has_file = input.has("file");
  const bool has_generator = input.has("generator");
  if (has_file == has_generator)
    input.fail(has_file ? "generator" : "file",
               "exactly one of input.file (a mesh file) and input.generator (icosphere, torus, "
               "box)");
  if (has_file) {
    settings.source = Source::kFile;
    settings.file = input.require<std::string>("file");
    if (!std::filesystem::is_regular_file(settings.file))
      input.fail("file", "an existing mesh file (.obj .ply .stl .off .vtk .vtp .vtu)");
  } else {
    settings.source = input.choice<Source>(
        "generator", Source::kIcosphere,
        {{"icosphere", Source::kIcosphere}, {"torus", Source::kTorus}, {"box", Source::kBox}});
  }
  settings.icosphere_level = input.get<int>("level", settings.icosphere_level, int_in_range(0, 9));
  settings.radius = input.get<double>("radius", settings.radius, positive());
  settings.major_radius = input.get<double>("major_radius", settings.major_radius, positive());
  settings.minor_radius = input.get<double>("minor_radius", settings.minor_radius, positive());
  if (settings.source == Source::kTorus && settings.minor_radius >= settings.major_radius)
    input.fail("minor_radius", "a number below input.major_radius");
  const auto segments = input.get<std::vector<double>>(
      "segments", {double(settings.torus_segments[0]), double(settings.torus_segments[1])});
  if (segments.size() != 2 || segments[0] < 3 || segments[1] < 3 ||
      segments[0] != int(segments[0]) || segments[1] != int(segments[1]))
    input.fail("segments", "two integers >= 3 (around the axis, around the tube)");
  settings.torus_segments = {int(segments[0]), int(segments[1])};
  const auto size = input.get<std::array<double, 3>>("size", {1.0, 1.0, 1.0});
  if (size[0] <= 0 || size[1] <= 0 || size[2] <= 0)
    input.fail("size", "three positive numbers");
  settings.box_size = geom::Vec3(size[0], size[1], size[2]);
  settings.box_cells_per_edge =
      input.get<int>("cells_per_edge", settings.box_cells_per_edge, int_in_range(1, 4096));

  settings.subdivision_levels =
      section.get<int>("subdivision_levels", settings.subdivision_levels, int_in_range(0, 6));
  settings.noise_amplitude =
      section.get<double>("noise_amplitude", settings.noise_amplitude, non_negative());
  return settings;
}

} // namespace texsim::pipelines::mesh_prep
