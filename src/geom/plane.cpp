#include "core/error.hpp"
#include "geom/generators.hpp"

namespace texsim::geom {

TriangleMesh plane(const Vec3& size, int cells_per_edge) {
  TEXSIM_VERIFY(size.x() > 0 && size.y() > 0 && cells_per_edge >= 1 && cells_per_edge <= 4096,
                "plane needs a positive size and 1 to 4096 cells per edge, got "
                    << size.x() << " x " << size.y() << " and " << cells_per_edge);
  const int n = cells_per_edge;
  TriangleMesh mesh;
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i)
      mesh.positions.emplace_back(size.x() * i / n, size.y() * j / n, 0.0);
  const auto vertex = [n](int i, int j) { return std::int32_t(j * (n + 1) + i); };
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      mesh.triangles.push_back({vertex(i, j), vertex(i + 1, j), vertex(i + 1, j + 1)});
      mesh.triangles.push_back({vertex(i, j), vertex(i + 1, j + 1), vertex(i, j + 1)});
    }
  return mesh;
}

} // namespace texsim::geom
