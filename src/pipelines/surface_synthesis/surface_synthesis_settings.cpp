#include "pipelines/surface_synthesis/surface_synthesis_settings.hpp"

#include "core/error.hpp"
#include "geom/point_expression.hpp"

#include <algorithm>
#include <cctype>
#include <cstdio>

namespace texsim::pipelines::surface_synthesis {
namespace {

/// Wei-Levoy's sizes (Section 4), coarsest first; more levels repeat the finest.
std::vector<NeighbourhoodShape> default_neighbourhoods(int levels) {
  std::vector<NeighbourhoodShape> shapes{{1, 1, 1}, {3, 3, 2}, {5, 5, 2}, {7, 7, 2}};
  while (int(shapes.size()) < levels)
    shapes.push_back(shapes.back());
  if (levels < int(shapes.size())) // fewer levels: keep the finest sizes, the coarsest one-level
    shapes.erase(shapes.begin(), shapes.end() - levels);
  shapes.front().levels = 1;
  return shapes;
}

/// "RxC,k" with odd R, C and k 1 or 2.
NeighbourhoodShape parse_shape(const ConfigSection& section, const std::string& text) {
  NeighbourhoodShape shape;
  char x = 0, comma = 0;
  int used = 0;
  const bool parsed = std::sscanf(text.c_str(), "%d%c%d%c%d%n", &shape.rows, &x, &shape.cols,
                                  &comma, &shape.levels, &used) == 5 &&
                      used == int(text.size()) && (x == 'x' || x == 'X') && comma == ',';
  if (!parsed || shape.rows < 1 || shape.cols < 1 || shape.rows % 2 == 0 || shape.cols % 2 == 0 ||
      shape.rows > 15 || shape.cols > 15 || (shape.levels != 1 && shape.levels != 2))
    section.fail("neighbourhoods", "entries \"RxC,k\" with odd R and C up to 15 and k 1 or 2 "
                                   "(Wei-Levoy's {7x7,2}); \"" +
                                       text + "\" is not one");
  return shape;
}

ExemplarSettings read_exemplar(const ConfigSection& section) {
  ExemplarSettings exemplar;
  const bool has_image = section.has("image"), has_procedural = section.has("procedural");
  if (has_image == has_procedural)
    section.fail("image", "exactly one of `image: <PNG or JPEG file>` and `procedural: "
                          "stripes|lattice|grid`");
  if (has_image) {
    exemplar.image = section.require<std::string>("image");
  } else {
    exemplar.procedural =
        section.choice<ProceduralExemplar>("procedural", ProceduralExemplar::none,
                                           {{"stripes", ProceduralExemplar::stripes},
                                            {"lattice", ProceduralExemplar::lattice},
                                            {"grid", ProceduralExemplar::grid}});
    exemplar.size = section.get<int>("size", exemplar.size, int_in_range(8, 1024));
    // Stripes default to 8 pixels a period: wider ones outgrow the default neighbourhoods and the
    // synthesis settles on one colour (docs/surface_synthesis.md, "Collapse to one colour").
    const int default_periods = exemplar.procedural == ProceduralExemplar::stripes
                                    ? std::max(1, exemplar.size / 8)
                                    : exemplar.periods;
    exemplar.periods = section.get<int>("periods", default_periods, int_in_range(1, 64));
  }
  exemplar.reduce = section.get<int>("reduce", exemplar.reduce, [](int f) {
    return f >= 1 && f <= 64 && (f & (f - 1)) == 0 ? std::string()
                                                   : std::string("a power of two from 1 to 64");
  });
  if (section.has("crop")) {
    const auto crop = section.require<std::vector<double>>("crop");
    std::array<int, 4> box{};
    bool whole = crop.size() == 4;
    for (std::size_t i = 0; whole && i < 4; ++i) {
      whole = crop[i] == double(int(crop[i])) && crop[i] >= (i < 2 ? 0 : 1);
      box[i] = whole ? int(crop[i]) : 0;
    }
    if (!whole)
      section.fail("crop", "[x, y, width, height] in whole pixels, width and height >= 1");
    exemplar.crop = box;
  }
  exemplar.border = section.choice<ExemplarBorder>(
      "border", exemplar.border,
      {{"toroidal", ExemplarBorder::toroidal}, {"discard", ExemplarBorder::discard}});
  return exemplar;
}

OrientationSettings read_orientation(const ConfigSection& section, const geom::MeshSource& mesh) {
  OrientationSettings orientation;
  orientation.mode = section.choice<OrientationMode>("mode", orientation.mode,
                                                     {{"random", OrientationMode::random},
                                                      {"field", OrientationMode::field},
                                                      {"relax", OrientationMode::relax}});
  orientation.mesh_fields = section.get<std::vector<std::string>>("mesh_fields", {});
  if (!orientation.mesh_fields.empty() && mesh.file.empty())
    section.fail("mesh_fields", "no mesh fields with a generated mesh (they are point arrays of "
                                "mesh.file)");
  if (orientation.mode == OrientationMode::field) {
    const auto field = section.require<std::vector<std::string>>("field");
    if (field.size() != 3)
      section.fail("field", "three expressions [fx, fy, fz] of x, y, z and the mesh_fields");
    for (int k = 0; k < 3; ++k) {
      orientation.field[std::size_t(k)] = field[std::size_t(k)];
      geom::PointExpression(field[std::size_t(k)], orientation.mesh_fields,
                            section.key_path("field"));
    }
  } else if (section.has("field")) {
    section.fail("field", "no `field` unless mode is field");
  }
  orientation.symmetry = section.get<int>("symmetry", orientation.symmetry, int_in_range(1, 8));
  orientation.sweeps = section.get<int>("sweeps", orientation.sweeps, int_in_range(0, 10000));
  return orientation;
}

geom::SurfaceCellsSettings read_retiling(const ConfigSection& section) {
  geom::SurfaceCellsSettings cells;
  auto& r = cells.relaxation;
  r.iterations = section.get<int>("iterations", r.iterations, non_negative_int());
  r.radius_factor = section.get<double>("radius_factor", r.radius_factor, positive());
  r.step = section.get<double>("step", r.step, in_range(0.0, 1.0));
  return cells;
}

} // namespace

SurfaceSynthesisSettings read_surface_synthesis_settings(const ConfigSection& section) {
  SurfaceSynthesisSettings settings;
  settings.mesh = geom::read_mesh_source(section.section("mesh"));
  settings.levels = section.get<int>("levels", settings.levels, int_in_range(1, 8));
  settings.vertices = section.get<std::int64_t>("vertices", settings.vertices, [&](std::int64_t n) {
    return n >= 64 && n <= (std::int64_t{1} << 30) ? std::string() : std::string("from 64 to 2^30");
  });
  int most_levels = 1;
  while ((settings.vertices >> (2 * most_levels)) >= 12)
    ++most_levels;
  if (settings.levels > most_levels)
    section.fail("levels", "at most " + std::to_string(most_levels) + " levels for " +
                               std::to_string(settings.vertices) +
                               " vertices: each coarser level has a quarter of the vertices and "
                               "the coarsest needs 12 (raise surface_synthesis.vertices)");
  settings.cells = read_retiling(section.section("retiling"));
  settings.exemplar = read_exemplar(section.section("exemplar"));
  if (section.has("neighbourhoods")) {
    const auto texts = section.require<std::vector<std::string>>("neighbourhoods");
    if (int(texts.size()) != settings.levels)
      section.fail("neighbourhoods", "one \"RxC,k\" per level, coarsest first (" +
                                         std::to_string(settings.levels) + " levels), got " +
                                         std::to_string(texts.size()));
    for (const auto& text : texts)
      settings.neighbourhoods.push_back(parse_shape(section, text));
    if (settings.neighbourhoods.front().levels != 1)
      section.fail("neighbourhoods", "a one-level first (coarsest) entry: there is no coarser "
                                     "level to read");
  } else {
    settings.neighbourhoods = default_neighbourhoods(settings.levels);
  }
  settings.orientation = read_orientation(section.section("orientation"), settings.mesh);
  settings.search = section.choice<SearchMethod>("search", settings.search,
                                                 {{"exhaustive", SearchMethod::exhaustive},
                                                  {"tsvq", SearchMethod::tsvq},
                                                  {"pruned", SearchMethod::pruned}});
  const auto atlas = section.section("atlas");
  settings.atlas.resolution = atlas.get<int>("resolution", settings.atlas.resolution, [](int r) {
    return r == 0 || (r >= 64 && r <= 16384) ? std::string()
                                             : std::string("0 (no atlas) or 64 to 16384");
  });
  settings.atlas.gutter = atlas.get<int>("gutter", settings.atlas.gutter, int_in_range(0, 16));
  settings.displacement_scale =
      section.section("displacement").get<double>("scale", 0.0, non_negative());
  return settings;
}

} // namespace texsim::pipelines::surface_synthesis
