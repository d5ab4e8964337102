#include "geom/submesh.hpp"

#include "core/error.hpp"

namespace texsim::geom {

Submesh extract_part(const TriangleMesh& mesh, const std::vector<int>& triangle_part, int part) {
  TEXSIM_VERIFY(triangle_part.size() == mesh.triangles.size(),
                "extract_part: " << triangle_part.size() << " part ids for "
                                 << mesh.triangles.size() << " triangles");
  std::vector<std::int32_t> chosen;
  for (std::int32_t t = 0; t < mesh.num_triangles(); ++t) {
    if (triangle_part[t] == part)
      chosen.push_back(t);
  }
  return extract_triangles(mesh, chosen);
}

Submesh extract_triangles(const TriangleMesh& mesh, std::span<const std::int32_t> triangles) {
  Submesh sub;
  std::vector<std::int32_t> local_of(mesh.positions.size(), -1);
  for (const std::int32_t t : triangles) {
    TEXSIM_ASSERT(t >= 0 && t < mesh.num_triangles(), "extract_triangles: triangle " << t);
    Triangle local{};
    for (int corner = 0; corner < 3; ++corner) {
      const std::int32_t v = mesh.triangles[t][corner];
      if (local_of[v] < 0) {
        local_of[v] = static_cast<std::int32_t>(sub.global_vertex.size());
        sub.global_vertex.push_back(v);
        sub.mesh.positions.push_back(mesh.positions[v]);
      }
      local[corner] = local_of[v];
    }
    sub.mesh.triangles.push_back(local);
    sub.global_triangle.push_back(t);
  }
  return sub;
}

} // namespace texsim::geom
