#include "geom/restricted_delaunay.hpp"

#include "geom/restricted_voronoi.hpp"

#include <algorithm>
#include <numeric>

namespace texsim::geom {

TriangleMesh restricted_delaunay(const TriangleMesh& surface, std::span<const Vec3> seeds,
                                 std::span<const std::int64_t> seed_ids) {
  std::vector<std::int32_t> all(std::size_t(surface.num_triangles()));
  std::iota(all.begin(), all.end(), 0);
  const auto pieces = restricted_voronoi_pieces(surface, all, seeds, seed_ids, true);

  std::vector<Triangle> triangles;
  for (const auto& piece : pieces) {
    const auto& labels = piece.edge_labels;
    const std::size_t n = labels.size();
    for (std::size_t k = 0; k < n; ++k) {
      const std::int32_t a = labels[(k + n - 1) % n], b = labels[k];
      if (a < 0 || b < 0 || a == b)
        continue;
      // Rotate so the smallest id comes first; the cyclic order (orientation) is kept.
      Triangle t{piece.seed, a, b};
      const auto first = std::min_element(t.begin(), t.end(), [&](auto x, auto y) {
        return seed_ids[std::size_t(x)] < seed_ids[std::size_t(y)];
      });
      std::rotate(t.begin(), first, t.end());
      triangles.push_back(t);
    }
  }
  const auto by_ids = [&](const Triangle& x, const Triangle& y) {
    for (int c = 0; c < 3; ++c)
      if (seed_ids[std::size_t(x[c])] != seed_ids[std::size_t(y[c])])
        return seed_ids[std::size_t(x[c])] < seed_ids[std::size_t(y[c])];
    return false;
  };
  std::sort(triangles.begin(), triangles.end(), by_ids);
  triangles.erase(std::unique(triangles.begin(), triangles.end()), triangles.end());

  TriangleMesh mesh;
  mesh.positions.assign(seeds.begin(), seeds.end());
  mesh.triangles = std::move(triangles);
  return mesh;
}

} // namespace texsim::geom
