#include "pipelines/surface_synthesis/level_stencils.hpp"

#include "pipelines/surface_synthesis/level_part.hpp"

#include <algorithm>
#include <numeric>
#include <optional>

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

/// Samples the patch flattened on `part` into `out` with the level's vertex ids; false when the
/// patch used a triangle whose neighbours the part may lack (it might differ from the patch on
/// the whole level).
bool sample_on_level(const LevelPart& part, const FlattenedPatch& patch,
                     std::span<const Eigen::Vector2d> positions, std::span<SampleWeights> out) {
  sample_patch(patch, positions, out);
  for (SampleWeights& sample : out)
    if (sample.covered())
      for (std::int32_t& vertex : sample.vertices)
        vertex = part.global_vertex(vertex);
  return std::all_of(patch.triangles.begin(), patch.triangles.end(),
                     [&](std::int32_t t) { return part.complete(t); });
}

/// Flattens the stencils' patches on LevelParts of the level and the coarser level.
struct StencilPatches {
  const par::Comm& comm;
  const RetiledLevel& level;
  std::span<const geom::Vec3> positions, normals, directions;
  const RetiledLevel* coarser;
  std::span<const ParentFace> parents;
  /// The positions of the parent faces' corners (sorted ids), fetched from their owners.
  std::vector<std::int64_t> corner_ids;
  std::vector<geom::Vec3> corner_positions;
  std::span<const Eigen::Vector2d> current_positions, coarser_positions;
  double current_radius, coarser_radius;

  /// The stencils of `vertices` (ascending) on parts grown `growth` times patch_reach() around
  /// them (and their parent faces); returns the vertices whose patches left their parts' complete
  /// triangles, whose stencils may differ from those on the whole level. Collective: every rank
  /// fetches its parts, with or without vertices.
  std::vector<std::int64_t> flatten(std::span<const std::int64_t> vertices, double growth,
                                    LevelStencils& stencils) const {
    std::vector<geom::Vec3> centres;
    for (const std::int64_t v : vertices)
      centres.push_back(positions[std::size_t(v - stencils.first)]);
    const LevelPart part(comm, level.triangles, centres, growth * patch_reach(current_radius));
    std::optional<LevelPart> coarser_part;
    if (stencils.coarser_count > 0) { // around the vertices and their parent faces' corners
      for (const std::int64_t v : vertices)
        if (const ParentFace& parent = parents[std::size_t(v - stencils.first)]; parent.found())
          for (const std::int32_t u : parent.vertices)
            centres.push_back(corner_positions[std::size_t(
                std::lower_bound(corner_ids.begin(), corner_ids.end(), u) - corner_ids.begin())]);
      coarser_part.emplace(comm, coarser->triangles, centres, growth * patch_reach(coarser_radius));
    }
    std::vector<char> escaped(vertices.size(), 0);
#pragma omp parallel
    {
      FlattenedPatch patch;
      // One scratch per part: a scratch sized for another mesh is cleared whole on every call.
      PatchScratch scratch, coarser_scratch;
#pragma omp for schedule(dynamic, 64)
      for (std::size_t i = 0; i < vertices.size(); ++i) {
        const auto v = std::size_t(vertices[i]);
        const auto local = std::size_t(vertices[i] - stencils.first);
        const geom::Vec3& n = normals[local];
        const geom::Vec3& s = directions[local];
        const TangentFrame frame{positions[local], s, n.cross(s), n};
        const auto around =
            part.topology().vertex_triangles().row(part.local_vertex(std::int32_t(v)));
        flatten_patch(part.mesh(), part.topology(), around, frame, current_radius, patch, scratch);
        bool inside = sample_on_level(
            part, patch, current_positions,
            {stencils.current.data() + local * stencils.current_count, stencils.current_count});
        if (stencils.coarser_count > 0 && parents[local].found()) {
          // The parent face's corners are centres of the coarser part, so it holds the face.
          const std::int32_t face = coarser_part->local_triangle(parents[local].triangle);
          flatten_patch(coarser_part->mesh(), coarser_part->topology(),
                        std::span<const std::int32_t>(&face, 1), frame, coarser_radius, patch,
                        coarser_scratch);
          inside = sample_on_level(*coarser_part, patch, coarser_positions,
                                   {stencils.coarser.data() + local * stencils.coarser_count,
                                    stencils.coarser_count}) &&
                   inside;
        }
        escaped[i] = !inside;
      }
    }
    std::vector<std::int64_t> again;
    for (std::size_t i = 0; i < vertices.size(); ++i)
      if (escaped[i])
        again.push_back(vertices[i]);
    return again;
  }
};

} // namespace

std::int64_t LevelStencils::uncovered() const {
  const auto count = [](const std::vector<SampleWeights>& samples) {
    return std::int64_t(std::count_if(samples.begin(), samples.end(),
                                      [](const SampleWeights& s) { return !s.covered(); }));
  };
  return count(current) + count(coarser);
}

LevelStencils build_level_stencils(const par::Comm& comm, const RetiledLevel& level,
                                   std::span<const geom::Vec3> positions,
                                   std::span<const geom::Vec3> normals,
                                   std::span<const geom::Vec3> directions,
                                   const RetiledLevel* coarser, std::span<const ParentFace> parents,
                                   const NeighbourhoodTemplate& layout, std::int64_t first,
                                   std::int64_t owned) {
  TEXSIM_VERIFY(coarser == nullptr || std::int64_t(parents.size()) == owned,
                parents.size() << " parent faces for " << owned << " owned vertices");
  TEXSIM_VERIFY(std::int64_t(directions.size()) == owned && std::int64_t(normals.size()) == owned &&
                    std::int64_t(positions.size()) == owned,
                directions.size() << " directions, " << normals.size() << " normals and "
                                  << positions.size() << " positions for " << owned
                                  << " owned vertices");
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

  std::vector<std::int64_t> corner_ids;
  if (coarser)
    for (const ParentFace& parent : parents)
      if (parent.found())
        corner_ids.insert(corner_ids.end(), parent.vertices.begin(), parent.vertices.end());
  std::sort(corner_ids.begin(), corner_ids.end());
  corner_ids.erase(std::unique(corner_ids.begin(), corner_ids.end()), corner_ids.end());
  std::vector<geom::Vec3> corner_positions;
  if (coarser)
    corner_positions = fetch_level_positions(comm, *coarser, corner_ids);
  const StencilPatches patches{comm,
                               level,
                               positions,
                               normals,
                               directions,
                               coarser,
                               parents,
                               std::move(corner_ids),
                               std::move(corner_positions),
                               current_positions,
                               coarser_positions,
                               current_radius,
                               coarser_radius};
  std::vector<std::int64_t> pending(static_cast<std::size_t>(owned));
  std::iota(pending.begin(), pending.end(), first);
  // Each round redoes the vertices whose patches left the last round's parts, on parts twice as
  // wide; a part as wide as the level holds every patch, so the rounds end. Every rank takes part
  // in every round (the parts are fetched together), until no rank has vertices left.
  for (double growth = 1;; growth *= 2) {
    int left = pending.empty() ? 0 : 1;
    MPI_Allreduce(MPI_IN_PLACE, &left, 1, MPI_INT, MPI_MAX, comm.raw);
    if (left == 0)
      break;
    pending = patches.flatten(pending, growth, stencils);
  }
  return stencils;
}

} // namespace texsim::pipelines::surface_synthesis
