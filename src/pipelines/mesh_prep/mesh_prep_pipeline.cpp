#include "pipelines/mesh_prep/mesh_prep_pipeline.hpp"

#include "core/log.hpp"
#include "geom/mesh_measures.hpp"
#include "geom/mesh_topology.hpp"
#include "geom/morton_order.hpp"
#include "geom/p1_matrices.hpp"
#include "geom/submesh.hpp"
#include "geom/triangle_quality.hpp"
#include "io/parallel_surface_writer.hpp"
#include "io/pvd_series.hpp"
#include "par/collective.hpp"

#include <mpi.h>

#include <algorithm>

namespace texsim::pipelines::mesh_prep {
namespace {

void record_measures(const geom::TriangleMesh& mesh, RunContext& ctx) {
  const geom::MeshTopology topology(mesh);
  const auto chi = topology.euler_characteristic();
  geom::Vec3 lo = mesh.positions.front(), hi = lo;
  for (const auto& p : mesh.positions) {
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
  auto& report = ctx.report;
  report.metric("vertices", mesh.num_vertices());
  report.metric("triangles", mesh.num_triangles());
  report.metric("edges", topology.num_edges());
  report.metric("boundary_edges", topology.boundary_edges().size());
  report.metric("euler_characteristic", chi);
  report.metric("manifold", topology.is_manifold());
  if (topology.is_closed() && topology.is_manifold())
    report.metric("genus", (2 - chi) / 2);
  report.metric("surface_area", geom::total_area(mesh));
  report.metric("mean_edge_length", geom::mean_edge_length(mesh));
  report.metric("bounding_box", {{lo.x(), lo.y(), lo.z()}, {hi.x(), hi.y(), hi.z()}});
  const auto quality = geom::triangle_quality(mesh);
  report.metric("triangle_quality", quality.metrics());
  log::info("triangle quality: " + quality.summary());
  log::info(log::cat("mesh: ", mesh.num_vertices(), " vertices, ", mesh.num_triangles(),
                     " triangles, area ", geom::total_area(mesh), ", Euler characteristic ", chi,
                     topology.is_closed() ? ", closed" : ", with boundary"));
}

/// Each rank writes the triangles of its part with per-vertex normals and areas.
std::filesystem::path write_partitioned(const geom::TriangleMesh& mesh, RunContext& ctx) {
  const auto part = geom::morton_triangle_parts(mesh, ctx.comm.size);
  const auto piece = geom::extract_part(mesh, part, ctx.comm.rank);

  const auto normals = geom::vertex_normals(mesh);
  const Eigen::VectorXd vertex_area = geom::lumped_mass(mesh);
  const auto triangle_area = geom::triangle_areas(mesh);
  const std::size_t n = piece.global_vertex.size();
  std::vector<double> xyz(3 * n), normal(3 * n), area(n);
  std::vector<std::int32_t> global_id(n);
  for (std::size_t v = 0; v < n; ++v) {
    const auto g = piece.global_vertex[v];
    for (int axis = 0; axis < 3; ++axis) {
      xyz[3 * v + axis] = mesh.positions[g][axis];
      normal[3 * v + axis] = normals[g][axis];
    }
    area[v] = vertex_area[g];
    global_id[v] = g;
  }
  std::vector<std::int64_t> triangles;
  for (const auto& tri : piece.mesh.triangles)
    triangles.insert(triangles.end(), tri.begin(), tri.end());
  const std::vector<std::int32_t> owner(piece.global_triangle.size(), ctx.comm.rank);
  std::vector<double> cell_area;
  for (const auto t : piece.global_triangle)
    cell_area.push_back(triangle_area[t]);

  io::SurfacePiece surface{
      xyz,
      triangles,
      {{"normal", 3, normal}, {"vertex_area", 1, area}, {"global_id", 1, global_id}},
      {{"rank", 1, owner}, {"area", 1, cell_area}}};

  long long local = static_cast<long long>(piece.global_triangle.size()), most = 0;
  MPI_Allreduce(&local, &most, 1, MPI_LONG_LONG, MPI_MAX, ctx.comm.raw);
  ctx.report.metric("partition_imbalance",
                    double(most) * ctx.comm.size / std::max<std::size_t>(1, mesh.triangles.size()));
  return io::write_parallel_surface(ctx.comm, ctx.settings.output_dir, "surface", surface,
                                    io::SurfaceFormat::vtp);
}

} // namespace

void MeshPrepPipeline::configure(const ConfigSection& section, const RunSettings&) {
  source_ = geom::read_mesh_source(section.section("input"));
}

void MeshPrepPipeline::run(RunContext& ctx) {
  geom::TriangleMesh mesh;
  {
    auto stage = ctx.timers.scope("build");
    geom::MeshBuildReport built;
    std::vector<char> creases;
    par::run_collectively(
        ctx.comm, [&] { mesh = geom::build_mesh(source_, ctx.settings.seed, &built, &creases); });
    geom::record_mesh_build(built, ctx.report);
    // mesh.crease_angle's edges after subdivision: kept sharp by its crease rules.
    ctx.report.metric("crease_edges", std::count(creases.begin(), creases.end(), 1));
    if (built.from_file)
      ctx.report.metric("repairs", built.repairs.changed() ? built.repairs.summary() : "none");
  }
  {
    auto stage = ctx.timers.scope("measure");
    record_measures(mesh, ctx);
  }
  auto stage = ctx.timers.scope("write");
  const auto surface = write_partitioned(mesh, ctx);
  const auto pvd_path = ctx.settings.output_dir / "surface.pvd";
  io::PvdSeries series(ctx.comm, pvd_path);
  series.add(0.0, std::filesystem::relative(surface, ctx.settings.output_dir).string());
  ctx.report.output(surface.string());
  ctx.report.output(pvd_path.string());
}

} // namespace texsim::pipelines::mesh_prep
