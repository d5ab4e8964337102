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

} // namespace texsim::pipelines::surface_synthesis
