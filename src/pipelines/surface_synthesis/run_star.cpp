#include "pipelines/surface_synthesis/run_star.hpp"

#include "core/error.hpp"
#include "par/id_runs.hpp"
#include "par/record_exchange.hpp"

#include <algorithm>
#include <array>
#include <vector>

namespace texsim::pipelines::surface_synthesis {

namespace {

/// A triangle on its way to a star: its corners' positions come from their owners, so a record is
/// 40 bytes instead of a geom::TriangleRecord's 112.
struct StarTriangle {
  std::int64_t id = -1;
  std::array<std::int64_t, 3> vertex{};
  geom::EdgeFlags creases{};
  std::array<char, 5> padding{}; ///< no indeterminate bytes on the wire
};

} // namespace

geom::LocalSurface run_star(const par::Comm& comm, const RetiledLevel& level) {
  const geom::LocalSurface& share = level.triangles.owned_surface();
  std::vector<std::vector<StarTriangle>> to_owners(std::size_t(comm.size));
  for (std::size_t k = 0; k < share.triangle_ids.size(); ++k) {
    StarTriangle triangle;
    triangle.id = share.triangle_ids[k];
    triangle.creases = share.triangle_creases[k];
    std::array<int, 3> owners{};
    for (std::size_t c = 0; c < 3; ++c) {
      triangle.vertex[c] = share.vertex_ids[std::size_t(share.mesh.triangles[k][c])];
      owners[c] = par::owner_of(level.rank_offsets, triangle.vertex[c]);
    }
    std::sort(owners.begin(), owners.end());
    for (std::size_t c = 0; c < 3; ++c)
      if (c == 0 || owners[c] != owners[c - 1])
        to_owners[std::size_t(owners[c])].push_back(triangle);
  }
  std::vector<StarTriangle> star = par::exchange_records(comm, std::move(to_owners));
  std::sort(star.begin(), star.end(),
            [](const StarTriangle& a, const StarTriangle& b) { return a.id < b.id; });
  std::vector<std::int64_t> ids, corners;
  std::vector<std::array<std::int64_t, 3>> triangle_corners;
  std::vector<geom::EdgeFlags> creases;
  for (const StarTriangle& triangle : star) {
    ids.push_back(triangle.id);
    triangle_corners.push_back(triangle.vertex);
    creases.push_back(triangle.creases);
    corners.insert(corners.end(), triangle.vertex.begin(), triangle.vertex.end());
  }
  star = {};
  std::sort(corners.begin(), corners.end());
  corners.erase(std::unique(corners.begin(), corners.end()), corners.end());
  const auto positions = fetch_level_positions(comm, level, corners);
  return geom::LocalSurface::assemble(
      std::move(ids), triangle_corners, std::move(creases), [&](std::size_t k, int c) {
        return positions[std::size_t(
            std::lower_bound(corners.begin(), corners.end(), triangle_corners[k][std::size_t(c)]) -
            corners.begin())];
      });
}

std::int32_t star_run_begin(const geom::LocalSurface& star, std::int64_t first,
                            std::int64_t count) {
  const auto begin = std::lower_bound(star.vertex_ids.begin(), star.vertex_ids.end(), first);
  const auto local = std::int32_t(begin - star.vertex_ids.begin());
  TEXSIM_VERIFY(count == 0 ||
                    (std::int64_t(star.vertex_ids.size()) >= local + count &&
                     star.vertex_ids[std::size_t(local + count - 1)] == first + count - 1),
                "run star: the vertices " << first << " .. " << first + count - 1
                                          << " are not all in the run's triangles");
  return local;
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

geom::CsrAdjacency run_rings(const geom::LocalSurface& star, std::int64_t first,
                             std::int64_t count) {
  geom::CsrAdjacency rings = run_rings(star.mesh, star_run_begin(star, first, count), count);
  for (auto& q : rings.indices)
    q = std::int32_t(star.vertex_ids[std::size_t(q)]);
  return rings;
}

geom::CsrAdjacency run_rings(const RetiledLevel& level, int rank) {
  return run_rings(level.star, level.run_begin(rank),
                   level.run_begin(rank + 1) - level.run_begin(rank));
}

} // namespace texsim::pipelines::surface_synthesis
