#pragma once
/// The `mesh_prep:` section: where the surface comes from and what is done to it.
#include "core/config.hpp"
#include "geom/triangle_mesh.hpp"

#include <array>
#include <filesystem>

namespace texsim::pipelines::mesh_prep {

enum class Source { kFile, kIcosphere, kTorus, kBox };

struct MeshPrepSettings {
  Source source = Source::kIcosphere;
  std::filesystem::path file;                ///< input.file (Source::kFile)
  int icosphere_level = 3;                   ///< input.level
  double radius = 1.0;                       ///< input.radius (icosphere)
  double major_radius = 1.0;                 ///< input.major_radius (torus)
  double minor_radius = 0.35;                ///< input.minor_radius (torus)
  std::array<int, 2> torus_segments{48, 24}; ///< input.segments: around the axis, around the tube
  geom::Vec3 box_size{1.0, 1.0, 1.0};        ///< input.size (box)
  int box_cells_per_edge = 8;                ///< input.cells_per_edge (box)
  int subdivision_levels = 0;                ///< subdivision_levels: Loop subdivision steps
  double noise_amplitude = 0.0;              ///< noise_amplitude: times the mean edge length
};

/// Reads and validates the section; a missing input file is reported here, before any work.
MeshPrepSettings read_mesh_prep_settings(const ConfigSection& section);

} // namespace texsim::pipelines::mesh_prep
