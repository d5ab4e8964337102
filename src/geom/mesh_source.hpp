#pragma once
/// Where a pipeline's surface comes from, as a config section: a mesh file or a generator, then
/// optional Loop subdivision and seeded normal noise. Shared by every surface pipeline:
///   input: {file: data/meshes/bunny00.off, subdivision_levels: 1}
///   input: {generator: box, size: [1, 1, 1], cells_per_edge: 24, noise_amplitude: 0.1}
#include "core/config.hpp"
#include "geom/mesh_validation.hpp"
#include "geom/triangle_mesh.hpp"

#include <array>
#include <cstdint>
#include <filesystem>

namespace texsim::geom {

enum class MeshGenerator { kNone, kIcosphere, kTorus, kBox };

struct MeshSource {
  std::filesystem::path file;                     ///< file: a mesh file (when generator is kNone)
  MeshGenerator generator = MeshGenerator::kNone; ///< generator: icosphere, torus or box
  int icosphere_level = 3;                        ///< level (icosphere)
  double radius = 1.0;                            ///< radius (icosphere)
  double major_radius = 1.0;                      ///< major_radius (torus)
  double minor_radius = 0.35;                     ///< minor_radius (torus)
  std::array<int, 2> torus_segments{48, 24};      ///< segments: around the axis, around the tube
  Vec3 box_size{1.0, 1.0, 1.0};                   ///< size (box)
  int box_cells_per_edge = 8;                     ///< cells_per_edge (box)
  double scale = 1.0; ///< scale: factor on every coordinate (sets the pattern size of RD runs)
  int subdivision_levels = 0;   ///< subdivision_levels: Loop subdivision steps
  double noise_amplitude = 0.0; ///< noise_amplitude: times the mean edge length
};

/// Reads the section; exactly one of `file` and `generator` must be given, and a file must exist.
/// Throws InputError naming the key path.
MeshSource read_mesh_source(const ConfigSection& section);

/// Reads (with the documented repairs of geom::repair, reported through `repairs` when not null)
/// or generates the mesh, scales it, refines it and perturbs it with noise keyed by `seed`. Serial;
/// the same on every rank.
TriangleMesh build_mesh(const MeshSource& source, std::uint64_t seed,
                        RepairReport* repairs = nullptr);

} // namespace texsim::geom
