#include "core/error.hpp"
#include "geom/generators.hpp"

#include <cmath>

namespace texsim::geom {

TriangleMesh torus(double major, double minor, int n_major, int n_minor) {
  TEXSIM_VERIFY(major > minor && minor > 0.0,
                "torus: radii major " << major << ", minor " << minor << " need major > minor > 0");
  TEXSIM_VERIFY(n_major >= 3 && n_minor >= 3,
                "torus: resolution " << n_major << " x " << n_minor << " needs at least 3 x 3");
  TriangleMesh mesh;
  mesh.positions.reserve(static_cast<std::size_t>(n_major) * n_minor);
  for (int i = 0; i < n_major; ++i) {
    const double u = 2.0 * M_PI * i / n_major;
    for (int j = 0; j < n_minor; ++j) {
      const double v = 2.0 * M_PI * j / n_minor;
      const double ring = major + minor * std::cos(v);
      mesh.positions.emplace_back(ring * std::cos(u), ring * std::sin(u), minor * std::sin(v));
    }
  }
  const auto id = [&](int i, int j) { return (i % n_major) * n_minor + (j % n_minor); };
  mesh.triangles.reserve(2 * mesh.positions.size());
  for (int i = 0; i < n_major; ++i) {
    for (int j = 0; j < n_minor; ++j) {
      // d/du x d/dv points away from the tube's centre line: (u, v) order is counter-clockwise.
      mesh.triangles.push_back({id(i, j), id(i + 1, j), id(i + 1, j + 1)});
      mesh.triangles.push_back({id(i, j), id(i + 1, j + 1), id(i, j + 1)});
    }
  }
  return mesh;
}

} // namespace texsim::geom
