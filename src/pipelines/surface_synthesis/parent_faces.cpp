#include "pipelines/surface_synthesis/parent_faces.hpp"

#include "core/error.hpp"
#include "geom/mesh_measures.hpp"

namespace texsim::pipelines::surface_synthesis {

std::vector<ParentFace> find_parent_faces(std::span<const geom::Vec3> points,
                                          std::span<const geom::Vec3> normals,
                                          const geom::TriangleMesh& coarse,
                                          const geom::AabbTree& coarse_tree) {
  std::vector<ParentFace> parents(points.size());
#pragma omp parallel for schedule(static)
  for (std::int64_t i = 0; i < std::int64_t(points.size()); ++i) {
    const auto hit = coarse_tree.nearest_line_hit(points[std::size_t(i)], normals[std::size_t(i)]);
    if (!hit)
      continue;
    auto& parent = parents[std::size_t(i)];
    parent.triangle = hit->triangle;
    parent.vertices = coarse.triangles[std::size_t(hit->triangle)];
    const auto& corners = parent.vertices;
    parent.weights = geom::barycentric_weights(
        coarse.positions[std::size_t(corners[0])], coarse.positions[std::size_t(corners[1])],
        coarse.positions[std::size_t(corners[2])], hit->point);
  }
  return parents;
}

std::vector<ParentFace> find_parent_faces(const par::Comm& comm,
                                          std::span<const std::int64_t> rank_offsets,
                                          std::span<const geom::Vec3> points,
                                          std::span<const geom::Vec3> normals,
                                          const geom::TriangleMesh& coarse) {
  TEXSIM_VERIFY(rank_offsets.size() == std::size_t(comm.size) + 1 &&
                    rank_offsets.back() == std::int64_t(points.size()),
                "find_parent_faces: rank_offsets do not split the points");
  const auto first = std::size_t(rank_offsets[std::size_t(comm.rank)]);
  const auto count = std::size_t(rank_offsets[std::size_t(comm.rank) + 1]) - first;
  TEXSIM_VERIFY(normals.size() == count,
                "find_parent_faces: " << normals.size() << " normals for a run of " << count);
  return find_parent_faces(points.subspan(first, count), normals, coarse, geom::AabbTree(coarse));
}

} // namespace texsim::pipelines::surface_synthesis
