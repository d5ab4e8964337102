#include "pipelines/surface_synthesis/level_part.hpp"

#include "core/error.hpp"
#include "geom/point_halo.hpp"

#include <algorithm>

namespace texsim::pipelines::surface_synthesis {

struct LevelPart::Selection {
  geom::Submesh part;
  std::vector<char> complete;
};

namespace {

std::int32_t find_sorted(const std::vector<std::int32_t>& ids, std::int32_t id) {
  const auto at = std::lower_bound(ids.begin(), ids.end(), id);
  return at != ids.end() && *at == id ? std::int32_t(at - ids.begin()) : -1;
}

} // namespace

LevelPart::LevelPart(const par::Comm& comm, const geom::DistributedTriangles& level,
                     std::span<const geom::Vec3> centres, double reach)
    : LevelPart([&] {
        TEXSIM_VERIFY(reach > 0, "level part: reach " << reach << " must be positive");
        const auto boxes = geom::covering_boxes(centres, reach, reach);
        const geom::LocalSurface window = level.window(comm, boxes);
        // A triangle with a corner near the centres is in the part; one with all three corners
        // near is complete, since every triangle sharing one of those corners is in the part.
        const auto near = geom::inside_boxes(window.mesh.positions, boxes);
        Selection chosen;
        std::vector<std::int32_t> local_of(window.mesh.positions.size(), -1);
        std::vector<std::size_t> taken; // window triangles in the part
        for (std::size_t t = 0; t < window.mesh.triangles.size(); ++t) {
          const geom::Triangle& corners = window.mesh.triangles[t];
          const int near_corners = near[std::size_t(corners[0])] + near[std::size_t(corners[1])] +
                                   near[std::size_t(corners[2])];
          if (near_corners == 0)
            continue;
          taken.push_back(t);
          chosen.part.global_triangle.push_back(std::int32_t(window.triangle_ids[t]));
          chosen.complete.push_back(near_corners == 3);
          for (const std::int32_t v : corners)
            local_of[std::size_t(v)] = 0;
        }
        // The window's vertices are in increasing id order, so the part's are too.
        for (std::size_t v = 0; v < window.mesh.positions.size(); ++v)
          if (local_of[v] == 0) {
            local_of[v] = std::int32_t(chosen.part.global_vertex.size());
            chosen.part.global_vertex.push_back(std::int32_t(window.vertex_ids[v]));
            chosen.part.mesh.positions.push_back(window.mesh.positions[v]);
          }
        for (const std::size_t t : taken) {
          const geom::Triangle& corners = window.mesh.triangles[t];
          chosen.part.mesh.triangles.push_back({local_of[std::size_t(corners[0])],
                                                local_of[std::size_t(corners[1])],
                                                local_of[std::size_t(corners[2])]});
        }
        return chosen;
      }()) {}

LevelPart::LevelPart(Selection&& selection)
    : part_(std::move(selection.part)), topology_(part_.mesh),
      complete_(std::move(selection.complete)) {}

std::int32_t LevelPart::local_vertex(std::int32_t global) const {
  return find_sorted(part_.global_vertex, global);
}

std::int32_t LevelPart::local_triangle(std::int32_t global) const {
  return find_sorted(part_.global_triangle, global);
}

double patch_reach(double patch_radius) {
  return 2.0 * patch_radius;
}

geom::CsrAdjacency run_rings(const geom::TriangleMesh& mesh, std::int64_t first,
                             std::int64_t count) {
  const auto in_run = [&](std::int32_t v) { return v >= first && v < first + count; };
  std::vector<std::int64_t> starts(std::size_t(count) + 1, 0);
  for (const geom::Triangle& corners : mesh.triangles)
    for (const std::int32_t v : corners)
      if (in_run(v))
        starts[std::size_t(v - first) + 1] += 2;
  for (std::size_t i = 1; i < starts.size(); ++i)
    starts[i] += starts[i - 1];
  std::vector<std::int32_t> listed(std::size_t(starts.back()));
  std::vector<std::int64_t> cursor(starts.begin(), starts.end() - 1);
  for (const geom::Triangle& corners : mesh.triangles)
    for (int c = 0; c < 3; ++c)
      if (const std::int32_t v = corners[std::size_t(c)]; in_run(v)) {
        auto& at = cursor[std::size_t(v - first)];
        listed[std::size_t(at++)] = corners[std::size_t((c + 1) % 3)];
        listed[std::size_t(at++)] = corners[std::size_t((c + 2) % 3)];
      }
  geom::CsrAdjacency rings;
  rings.offsets.push_back(0);
  for (std::int64_t i = 0; i < count; ++i) {
    const auto begin = listed.begin() + starts[std::size_t(i)];
    const auto end = listed.begin() + starts[std::size_t(i) + 1];
    std::sort(begin, end);
    rings.indices.insert(rings.indices.end(), begin, std::unique(begin, end));
    rings.offsets.push_back(std::int64_t(rings.indices.size()));
  }
  return rings;
}

} // namespace texsim::pipelines::surface_synthesis
