#pragma once
/// The `surface_synthesis:` config section (Wei & Levoy 2001), read into typed settings; see
/// config/surface_synthesis/*.yaml and docs/surface_synthesis.md for every key.
#include "core/config.hpp"
#include "geom/mesh_source.hpp"
#include "geom/surface_cells.hpp"
#include "pipelines/surface_synthesis/neighbourhood_search.hpp"

#include <array>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace texsim::pipelines::surface_synthesis {

enum class ExemplarBorder {
  toroidal, ///< neighbourhoods wrap around the exemplar (tileable textures)
  discard,  ///< only pixels whose whole neighbourhood lies inside are candidates
};

enum class ProceduralExemplar { none, stripes, lattice, grid };

struct ExemplarSettings {
  std::filesystem::path image;                              ///< image: PNG or JPEG file
  ProceduralExemplar procedural = ProceduralExemplar::none; ///< procedural: stripes|lattice|grid
  int size = 64; ///< size: side of a procedural exemplar, pixels
  /// periods: stripes or grid lines across a procedural exemplar (stripes: size / 8 unless given)
  int periods = 4;
  int reduce = 1; ///< reduce: power-of-two factor the image is shrunk by (Gaussian pyramid)
  /// crop: [x, y, width, height] of the (reduced) image; absent: the whole image
  std::optional<std::array<int, 4>> crop;
  ExemplarBorder border = ExemplarBorder::toroidal; ///< border
};

/// One level's neighbourhood {R x C, k} (Wei-Levoy Table 1): rows x cols samples at the level, and
/// with two levels ceil(rows / 2) x ceil(cols / 2) more on the coarser one.
struct NeighbourhoodShape {
  int rows = 1;
  int cols = 1;
  int levels = 1;
};

enum class OrientationMode { random, field, relax };

struct OrientationSettings {
  OrientationMode mode = OrientationMode::random; ///< mode: random|field|relax
  /// field: three expressions of x, y, z (and the mesh arrays named in mesh_fields)
  std::array<std::string, 3> field{"1", "0", "0"};
  std::vector<std::string> mesh_fields; ///< mesh_fields: point arrays of mesh.file usable in field
  int symmetry = 2;                     ///< symmetry: n of the n-way relaxation
  int sweeps = 30;                      ///< sweeps: relaxation sweeps per level
};

struct AtlasOutputSettings {
  int resolution = 1024; ///< resolution: atlas.png side, texels (0: no atlas)
  int gutter = 2;        ///< gutter: texels between charts
};

struct SurfaceSynthesisSettings {
  geom::MeshSource mesh;
  std::int64_t vertices = 24576;    ///< vertices: retiled vertices of the finest level (the scale)
  int levels = 4;                   ///< levels: mesh and exemplar pyramid levels
  geom::SurfaceCellsSettings cells; ///< retiling: relaxation settings of Turk's retiling
  ExemplarSettings exemplar;
  /// neighbourhoods: one {R x C, k} per level, coarsest first (Wei-Levoy: {1x1,1}, {3x3,2},
  /// {5x5,2}, {7x7,2})
  std::vector<NeighbourhoodShape> neighbourhoods;
  OrientationSettings orientation;
  SearchMethod search = SearchMethod::exhaustive; ///< search: exhaustive|tsvq|pruned
  AtlasOutputSettings atlas;
  double displacement_scale = 0; ///< displacement.scale: luminance as height (0: none)

  /// The shape used on pyramid level `level` (0 = finest).
  const NeighbourhoodShape& shape(int level) const {
    return neighbourhoods[std::size_t(levels - 1 - level)];
  }
};

SurfaceSynthesisSettings read_surface_synthesis_settings(const ConfigSection& section);

} // namespace texsim::pipelines::surface_synthesis
