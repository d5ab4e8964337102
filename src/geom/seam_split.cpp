#include "geom/seam_split.hpp"

#include "core/error.hpp"

#include <map>
#include <tuple>

namespace texsim::geom {

SeamSplitMesh split_at_seams(const TriangleMesh& mesh,
                             const std::vector<std::array<Eigen::Vector2d, 3>>& corner_uv) {
  TEXSIM_VERIFY(corner_uv.size() == mesh.triangles.size(),
                "split_at_seams: " << corner_uv.size() << " uv triples for "
                                   << mesh.triangles.size() << " triangles");
  SeamSplitMesh split;
  std::map<std::tuple<std::int32_t, double, double>, std::int32_t> copy_of;
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    Triangle corners{};
    for (std::size_t c = 0; c < 3; ++c) {
      const auto v = mesh.triangles[t][c];
      const auto& uv = corner_uv[t][c];
      const auto [at, added] =
          copy_of.emplace(std::tuple{v, uv.x(), uv.y()}, std::int32_t(split.uv.size()));
      if (added) {
        split.mesh.positions.push_back(mesh.positions[std::size_t(v)]);
        split.uv.push_back(uv);
        split.original_vertex.push_back(v);
      }
      corners[c] = at->second;
    }
    split.mesh.triangles.push_back(corners);
  }
  return split;
}

} // namespace texsim::geom
