#include "geom/mesh_source.hpp"

#include "core/log.hpp"
#include "geom/crease_edges.hpp"
#include "geom/generators.hpp"
#include "geom/mesh_measures.hpp"
#include "geom/mesh_reader.hpp"

#include <vector>

namespace texsim::geom {

MeshSource read_mesh_source(const ConfigSection& section) {
  MeshSource source;
  const bool has_file = section.has("file");
  const bool has_generator = section.has("generator");
  if (has_file == has_generator)
    section.fail(has_file ? "generator" : "file",
                 "exactly one of file (a mesh file) and generator (icosphere, torus, box, plane)");
  if (has_file) {
    source.file = section.require<std::string>("file");
    if (!std::filesystem::is_regular_file(source.file))
      section.fail("file", "an existing mesh file (.obj .ply .stl .off .vtk .vtp .vtu)");
  } else {
    source.generator = section.choice<MeshGenerator>("generator", MeshGenerator::kIcosphere,
                                                     {{"icosphere", MeshGenerator::kIcosphere},
                                                      {"torus", MeshGenerator::kTorus},
                                                      {"box", MeshGenerator::kBox},
                                                      {"plane", MeshGenerator::kPlane}});
  }
  source.icosphere_level = section.get<int>("level", source.icosphere_level, int_in_range(0, 9));
  source.radius = section.get<double>("radius", source.radius, positive());
  source.major_radius = section.get<double>("major_radius", source.major_radius, positive());
  source.minor_radius = section.get<double>("minor_radius", source.minor_radius, positive());
  if (source.generator == MeshGenerator::kTorus && source.minor_radius >= source.major_radius)
    section.fail("minor_radius", "a number below major_radius");
  const auto segments = section.get<std::vector<double>>(
      "segments", {double(source.torus_segments[0]), double(source.torus_segments[1])});
  if (segments.size() != 2 || segments[0] < 3 || segments[1] < 3 ||
      segments[0] != int(segments[0]) || segments[1] != int(segments[1]))
    section.fail("segments", "two integers >= 3 (around the axis, around the tube)");
  source.torus_segments = {int(segments[0]), int(segments[1])};
  const auto size = section.get<std::array<double, 3>>("size", {1.0, 1.0, 1.0});
  if (size[0] <= 0 || size[1] <= 0 || size[2] <= 0)
    section.fail("size", "three positive numbers");
  source.box_size = Vec3(size[0], size[1], size[2]);
  source.box_cells_per_edge =
      section.get<int>("cells_per_edge", source.box_cells_per_edge, int_in_range(1, 4096));
  source.scale = section.get<double>("scale", source.scale, positive());
  source.subdivision_levels =
      section.get<int>("subdivision_levels", source.subdivision_levels, int_in_range(0, 6));
  source.crease_angle =
      section.get<double>("crease_angle", source.crease_angle, in_range(0.0, 180.0));
  source.noise_amplitude =
      section.get<double>("noise_amplitude", source.noise_amplitude, non_negative());
  source.repair.strict = section.choice<bool>("repair", false, {{"fix", false}, {"strict", true}});
  if (source.repair.strict)
    source.repair.split_non_manifold = false;
  source.repair.min_component_fraction = section.get<double>(
      "min_component_fraction", source.repair.min_component_fraction, in_range(0.0, 1.0));
  source.repair.fill_holes = section.get<bool>("fill_holes", source.repair.fill_holes);
  if (source.repair.strict && source.repair.fill_holes)
    section.fail("fill_holes", "false with repair: strict (strict changes nothing)");
  if (section.has("remesh")) {
    const auto remesh = section.section("remesh");
    RemeshOptions options;
    options.edge_length = remesh.require<double>("edge_length", positive());
    options.iterations = remesh.get<int>("iterations", options.iterations, int_in_range(1, 100));
    source.remesh = options;
  }
  return source;
}

MeshRepairOptions MeshSource::fix_repair_options() {
  MeshRepairOptions options;
  options.split_non_manifold = true;
  options.min_component_fraction = 0.01;
  return options;
}

namespace {

/// The icosphere level rank 0 generates; the levels above it are sphere rounds on the parts.
int coarse_icosphere_level(const MeshSource& source) {
  if (source.generator != MeshGenerator::kIcosphere || source.remesh)
    return source.icosphere_level; // remeshing needs the whole surface
  int level = 0;
  while (level < source.icosphere_level &&
         (std::int64_t{20} << (2 * level)) < kDistributedRefinementTriangles)
    ++level;
  return level;
}

TriangleMesh load_or_generate(const MeshSource& source, RepairReport* repairs) {
  switch (source.generator) {
  case MeshGenerator::kNone:
    return read_mesh(source.file, source.repair, repairs);
  case MeshGenerator::kIcosphere:
    return icosphere(coarse_icosphere_level(source), source.radius);
  case MeshGenerator::kTorus:
    return torus(source.major_radius, source.minor_radius, source.torus_segments[0],
                 source.torus_segments[1]);
  case MeshGenerator::kBox:
    return box(source.box_size, source.box_cells_per_edge);
  case MeshGenerator::kPlane:
    return plane(source.box_size, source.box_cells_per_edge);
  }
  TEXSIM_VERIFY(false, "unhandled mesh generator");
}

} // namespace

SurfacePlan plan_surface(const MeshSource& source, MeshBuildReport* report) {
  MeshBuildReport built;
  built.from_file = source.generator == MeshGenerator::kNone;
  built.file = source.file;
  built.strict = source.repair.strict;
  SurfacePlan plan;
  TriangleMesh& mesh = plan.coarse;
  mesh = load_or_generate(source, &built.repairs);
  for (auto& position : mesh.positions) {
    position *= source.scale;
    // Beyond this, squared lengths and areas overflow to infinity in every later computation.
    if (!(position.cwiseAbs().maxCoeff() <= 1e100))
      TEXSIM_INPUT_ERROR("scale: " << source.scale << " makes a vertex coordinate "
                                   << position.cwiseAbs().maxCoeff()
                                   << "; expected coordinates up to 1e100 in magnitude");
  }
  if (source.remesh) {
    built.remeshed = true;
    built.remesh_edge_length = source.remesh->edge_length;
    built.vertices_before_remesh = mesh.num_vertices();
    built.triangles_before_remesh = mesh.num_triangles();
    mesh = remesh_isotropic(mesh, *source.remesh);
    // Remeshing next to the coincident copies of split vertices can leave triangles of zero area;
    // drop them (and whatever that leaves) without merging the copies again.
    auto cleanup = MeshSource::fix_repair_options();
    cleanup.merge_coincident_vertices = false;
    cleanup.min_component_fraction = source.repair.min_component_fraction;
    built.remesh_repairs =
        repair(mesh, cleanup, built.from_file ? source.file.string() : "remeshed surface");
  }
  if (report != nullptr)
    *report = built;
  RefinementStep sphere{RefinementStep::Rule::kSphere, {0, 0, 0}, source.radius * source.scale};
  plan.refinement.assign(std::size_t(source.icosphere_level - coarse_icosphere_level(source)),
                         sphere);
  int serial_loop = 0;
  while (serial_loop < source.subdivision_levels && plan.refinement.empty() &&
         (std::int64_t(mesh.num_triangles()) << (2 * serial_loop)) <
             kDistributedRefinementTriangles)
    ++serial_loop;
  if (source.crease_angle < 180.0)
    plan.creases = crease_edges(mesh, MeshTopology(mesh), source.crease_angle);
  if (serial_loop > 0) {
    const std::vector<RefinementStep> rounds(std::size_t(serial_loop), RefinementStep{});
    std::vector<char> fine_creases;
    mesh = refine(mesh, rounds, plan.creases, &fine_creases);
    plan.creases = std::move(fine_creases);
  }
  plan.refinement.insert(plan.refinement.end(),
                         std::size_t(source.subdivision_levels - serial_loop), RefinementStep{});
  return plan;
}

TriangleMesh build_mesh(const MeshSource& source, std::uint64_t seed, MeshBuildReport* report,
                        std::vector<char>* creases) {
  auto plan = plan_surface(source, report);
  TriangleMesh mesh = refine(plan.coarse, plan.refinement, plan.creases, creases);
  if (source.noise_amplitude > 0)
    mesh = noisy(mesh, source.noise_amplitude * mean_edge_length(mesh), seed);
  return mesh;
}

void record_mesh_build(const MeshBuildReport& report, RunReport& run) {
  if (report.from_file) {
    const auto& repairs = report.repairs;
    auto metrics = repairs.metrics();
    metrics["mode"] = report.strict ? "strict" : "fix";
    run.metric("mesh_repair", metrics);
    log::info(log::cat("read ", report.file.string(),
                       " (mesh.repair: ", report.strict ? "strict" : "fix",
                       "); repairs: ", repairs.changed() ? repairs.summary() : "none"));
  }
  if (report.remeshed) {
    run.metric("mesh_remesh", {{"edge_length", report.remesh_edge_length},
                               {"vertices_before", report.vertices_before_remesh},
                               {"triangles_before", report.triangles_before_remesh},
                               {"repairs_after", report.remesh_repairs.metrics()}});
    log::info(log::cat("remeshed towards edge length ", report.remesh_edge_length, " from ",
                       report.vertices_before_remesh, " vertices, ", report.triangles_before_remesh,
                       " triangles; repairs after: ",
                       report.remesh_repairs.changed() ? report.remesh_repairs.summary() : "none"));
  }
}

} // namespace texsim::geom
