#pragma once
/// Where a pipeline's surface comes from, as a config section: a mesh file (repaired) or a
/// generator, then optional isotropic remeshing, Loop subdivision and seeded normal noise. Shared
/// by every surface pipeline:
///   input: {file: data/meshes/bunny00.off, subdivision_levels: 1}
///   mesh: {file: data/scans/colin27_head_2mm_mc.ply, repair: fix, remesh: {edge_length: 2.5}}
///   input: {generator: box, size: [1, 1, 1], cells_per_edge: 24, noise_amplitude: 0.1}
#include "core/config.hpp"
#include "core/run_report.hpp"
#include "geom/mesh_remesh.hpp"
#include "geom/mesh_validation.hpp"
#include "geom/patch_refinement.hpp"
#include "geom/triangle_mesh.hpp"

#include <array>
#include <cstdint>
#include <filesystem>
#include <optional>
#include <vector>

namespace texsim::geom {

enum class MeshGenerator { kNone, kIcosphere, kTorus, kBox, kPlane };

struct MeshSource {
  std::filesystem::path file;                     ///< file: a mesh file (when generator is kNone)
  MeshGenerator generator = MeshGenerator::kNone; ///< generator: icosphere, torus, box or plane
  int icosphere_level = 3;                        ///< level (icosphere)
  double radius = 1.0;                            ///< radius (icosphere)
  double major_radius = 1.0;                      ///< major_radius (torus)
  double minor_radius = 0.35;                     ///< minor_radius (torus)
  std::array<int, 2> torus_segments{48, 24};      ///< segments: around the axis, around the tube
  Vec3 box_size{1.0, 1.0, 1.0};                   ///< size (box; plane: x and y)
  int box_cells_per_edge = 8;                     ///< cells_per_edge (box, plane)
  double scale = 1.0; ///< scale: factor on every coordinate (sets the pattern size of RD runs)
  int subdivision_levels = 0; ///< subdivision_levels: Loop subdivision steps
  /// crease_angle (degrees; 180: none): edges whose triangles' normals differ by more are
  /// creases, flagged before subdivision and noise and kept sharp by Loop's crease rules, in the
  /// subdivision and in fem_rd's Loop basis.
  double crease_angle = 180.0;
  double noise_amplitude = 0.0; ///< noise_amplitude: times the mean edge length
  /// repair: fix (default: split non-manifold edges and vertices, orient, drop small components,
  /// optionally fill holes) or strict (refuse what needs repair); min_component_fraction (0.01:
  /// of the largest component's area), fill_holes (false). Files only.
  MeshRepairOptions repair = fix_repair_options();
  /// remesh: {edge_length: L, iterations: 3}: isotropic remeshing after `scale`, L in scaled units.
  std::optional<RemeshOptions> remesh;

  /// The repairs `mesh.repair: fix` makes by default.
  static MeshRepairOptions fix_repair_options();
};

/// Reads the section; exactly one of `file` and `generator` must be given, and a file must exist.
/// Throws InputError naming the key path.
MeshSource read_mesh_source(const ConfigSection& section);

/// What build_mesh() did to the file's mesh, for the log and summary.json.
struct MeshBuildReport {
  bool from_file = false;
  std::filesystem::path file;
  bool strict = false;
  RepairReport repairs;
  bool remeshed = false;
  double remesh_edge_length = 0;
  std::int64_t vertices_before_remesh = 0, triangles_before_remesh = 0;
  RepairReport remesh_repairs; ///< what the clean-up after remeshing removed
};

/// Rank 0 refines a surface no further than this many triangles (or than the config asks); the
/// rounds beyond are left to the ranks' parts (DistributedMesh). A fixed count, so the coarse
/// mesh, and with it every vertex id, is the same at any rank count.
inline constexpr std::int64_t kDistributedRefinementTriangles = 65536;

/// A surface as build_mesh() makes it, stopped where the refinement could go on in parallel: the
/// coarse mesh (an icosphere at a lower level, or Loop-refined only to
/// kDistributedRefinementTriangles) and the refinement rounds left (sphere rounds, then Loop
/// rounds). Noise is not applied.
struct SurfacePlan {
  TriangleMesh coarse;
  std::vector<RefinementStep> refinement;
  std::vector<char> creases; ///< per edge of MeshTopology(coarse); empty: none
};

/// Reads (with the repairs of geom::repair as `source.repair` says, reported through `report` when
/// not null) or generates the coarse mesh, scales it, remeshes it, flags its creases and refines
/// it up to the distributed threshold. Serial.
SurfacePlan plan_surface(const MeshSource& source, MeshBuildReport* report = nullptr);

/// plan_surface(), the remaining rounds (geom::refine) and noise along the normals keyed by `seed`
/// (noisy()): the whole surface, and its creases in `creases` when not null (per edge of its
/// MeshTopology; empty: none). Serial; the same on every rank.
TriangleMesh build_mesh(const MeshSource& source, std::uint64_t seed,
                        MeshBuildReport* report = nullptr, std::vector<char>* creases = nullptr);

/// Logs (rank 0) what build_mesh() repaired and remeshed and records it in `run` as the metrics
/// "mesh_repair" (mode and every count of RepairReport::metrics) and "mesh_remesh".
void record_mesh_build(const MeshBuildReport& report, RunReport& run);

} // namespace texsim::geom
