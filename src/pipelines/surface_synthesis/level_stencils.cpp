#include "pipelines/surface_synthesis/level_stencils.hpp"

#include <algorithm>

namespace texsim::pipelines::surface_synthesis {
namespace {

/// The patch must reach the farthest sample plus about one triangle, so the triangle holding a
/// sample near the rim is flattened too.
double patch_radius(std::span<const Eigen::Vector2d> positions, double spacing) {
  double radius = 0;
  for (const auto& p : positions)
    radius = std::max(radius, p.norm());
  return radius + spacing;
}

} // namespace

std::int64_t LevelStencils::uncovered() const {
  const auto count = [](const std::vector<SampleWeights>& samples) {
    return std::int64_t(std::count_if(samples.begin(), samples.end(),
                                      [](const SampleWeights& s) { return !s.covered(); }));
  };
  return count(current) + count(coarser);
}

LevelStencils build_level_stencils(const RetiledLevel& level, const geom::MeshTopology& topology,
                                   std::span<const geom::Vec3> directions,
                                   const RetiledLevel* coarser,
                                   const geom::MeshTopology* coarser_topology,
                                   std::span<const ParentFace> parents,
                                   const NeighbourhoodTemplate& layout, std::int64_t first,
                                   std::int64_t owned) {
  LevelStencils stencils;
  stencils.first = first;
  stencils.owned = owned;
  const double d = level.spacing;
  const auto current_positions = layout.current_positions(d);
  const auto coarser_positions = layout.coarser_positions(d);
  stencils.current_count = current_positions.size();
  stencils.coarser_count = coarser ? coarser_positions.size() : 0;
  stencils.current.resize(std::size_t(owned) * stencils.current_count);
  stencils.coarser.resize(std::size_t(owned) * stencils.coarser_count);
  const double current_radius = patch_radius(current_positions, d);
  const double coarser_radius = coarser ? patch_radius(coarser_positions, coarser->spacing) : 0;
  const auto& vertex_triangles = topology.vertex_triangles();

#pragma omp parallel
  {
    FlattenedPatch patch;
    PatchScratch scratch;
#pragma omp for schedule(dynamic, 64)
    for (std::int64_t local = 0; local < owned; ++local) {
      const auto v = std::size_t(first + local);
      const geom::Vec3& n = level.normals[v];
      const geom::Vec3& s = directions[v];
      const TangentFrame frame{level.mesh.positions[v], s, n.cross(s), n};
      const auto around = vertex_triangles.row(std::int32_t(v));
      flatten_patch(level.mesh, topology, around, frame, current_radius, patch, scratch);
      sample_patch(patch, current_positions,
                   {stencils.current.data() + std::size_t(local) * stencils.current_count,
                    stencils.current_count});
      if (stencils.coarser_count == 0 || !parents[v].found())
        continue;
      // The parent face's triangle id: the coarse triangle whose corners the parent lists.
      const std::int32_t face = parents[v].triangle;
      flatten_patch(coarser->mesh, *coarser_topology, std::span<const std::int32_t>(&face, 1),
                    frame, coarser_radius, patch, scratch);
      sample_patch(patch, coarser_positions,
                   {stencils.coarser.data() + std::size_t(local) * stencils.coarser_count,
                    stencils.coarser_count});
    }
  }
  return stencils;
}

} // namespace texsim::pipelines::surface_synthesis
