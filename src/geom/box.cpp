#include "core/error.hpp"
#include "geom/generators.hpp"

#include <vector>

namespace texsim::geom {

TriangleMesh box(const Vec3& size, int cells_per_edge) {
  TEXSIM_VERIFY((size.array() > 0.0).all(),
                "box: size (" << size.transpose() << ") must be positive");
  TEXSIM_VERIFY(cells_per_edge >= 1 && cells_per_edge <= 4096,
                "box: cells_per_edge " << cells_per_edge << " outside [1, 4096]");
  const int n = cells_per_edge;
  const auto lattice = [&](int i, int j, int k) {
    return (static_cast<std::size_t>(i) * (n + 1) + j) * (n + 1) + k;
  };
  // Vertices are the lattice points of the (n+1)^3 grid that lie on the surface, numbered in
  // lattice order; each face looks its corners up here, so faces share their edge vertices.
  TriangleMesh mesh;
  std::vector<std::int32_t> vertex_id(lattice(n, n, n) + 1, -1);
  for (int i = 0; i <= n; ++i) {
    for (int j = 0; j <= n; ++j) {
      for (int k = 0; k <= n; ++k) {
        const bool on_surface = i == 0 || i == n || j == 0 || j == n || k == 0 || k == n;
        if (on_surface) {
          vertex_id[lattice(i, j, k)] = mesh.num_vertices();
          const Eigen::Array3d fraction(i, j, k);
          mesh.positions.push_back(size.array() * (fraction / n - 0.5));
        }
      }
    }
  }
  for (int axis = 0; axis < 3; ++axis) {
    const int b = (axis + 1) % 3;
    const int c = (axis + 2) % 3;
    for (const int side : {0, n}) {
      const auto id = [&](int s, int t) {
        std::array<int, 3> ijk;
        ijk[axis] = side;
        ijk[b] = s;
        ijk[c] = t;
        return vertex_id[lattice(ijk[0], ijk[1], ijk[2])];
      };
      // e_b x e_c = e_axis: (s, t) order faces +axis; the face at side 0 is flipped.
      for (int s = 0; s < n; ++s) {
        for (int t = 0; t < n; ++t) {
          const auto p00 = id(s, t), p10 = id(s + 1, t), p11 = id(s + 1, t + 1), p01 = id(s, t + 1);
          if (side == n) {
            mesh.triangles.push_back({p00, p10, p11});
            mesh.triangles.push_back({p00, p11, p01});
          } else {
            mesh.triangles.push_back({p00, p11, p10});
            mesh.triangles.push_back({p00, p01, p11});
          }
        }
      }
    }
  }
  return mesh;
}

} // namespace texsim::geom
