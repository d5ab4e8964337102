#include "pipelines/surface_synthesis/parent_faces.hpp"

#include "core/error.hpp"
#include "geom/mesh_measures.hpp"
#include "par/record_exchange.hpp"

#include <array>
#include <cmath>

namespace texsim::pipelines::surface_synthesis {

namespace {

/// A point whose nearest crossing its rank's window could not vouch for, as every rank gets it.
struct OpenQuery {
  std::array<double, 3> origin, direction;
  std::int32_t rank;  ///< the rank that asks
  std::int32_t index; ///< the point's index in that rank's points
};

/// The nearest crossing of an open query among one rank's share of the triangles.
struct ShareCrossing {
  geom::TriangleRecord triangle;
  double t;
  std::int32_t index; ///< the query's index on the rank that asked
  std::int32_t padding = 0;
};

/// The parent face hit at origin + t direction: the triangle's id on the level, its corners' ids
/// and positions. The weights are the serial search's, from the same corners and hit point.
ParentFace parent_face(const geom::Vec3& origin, const geom::Vec3& direction, double t,
                       std::int64_t triangle, const std::array<std::int64_t, 3>& vertices,
                       const std::array<geom::Vec3, 3>& corners) {
  ParentFace parent;
  parent.triangle = std::int32_t(triangle);
  for (int c = 0; c < 3; ++c)
    parent.vertices[std::size_t(c)] = std::int32_t(vertices[std::size_t(c)]);
  parent.weights =
      geom::barycentric_weights(corners[0], corners[1], corners[2], origin + t * direction);
  return parent;
}

} // namespace

std::vector<ParentFace> find_parent_faces(std::span<const geom::Vec3> points,
                                          std::span<const geom::Vec3> normals,
                                          const geom::TriangleMesh& coarse,
                                          const geom::AabbTree& coarse_tree) {
  std::vector<ParentFace> parents(points.size());
#pragma omp parallel for schedule(static)
  for (std::int64_t i = 0; i < std::int64_t(points.size()); ++i) {
    const auto I = std::size_t(i);
    const auto hit = coarse_tree.nearest_line_crossing(points[I], normals[I]);
    if (!hit)
      continue;
    const geom::Triangle& corners = coarse.triangles[std::size_t(hit->triangle)];
    const auto& p = coarse.positions;
    parents[I] = parent_face(
        points[I], normals[I], hit->t, hit->triangle, {corners[0], corners[1], corners[2]},
        {p[std::size_t(corners[0])], p[std::size_t(corners[1])], p[std::size_t(corners[2])]});
  }
  return parents;
}

std::vector<ParentFace> find_parent_faces(const par::Comm& comm, std::span<const geom::Vec3> points,
                                          std::span<const geom::Vec3> normals,
                                          const geom::DistributedTriangles& coarse, double reach) {
  TEXSIM_VERIFY(normals.size() == points.size(),
                "find_parent_faces: " << normals.size() << " normals for " << points.size()
                                      << " points");
  TEXSIM_VERIFY(reach > 0, "find_parent_faces: reach " << reach);
  std::vector<ParentFace> parents(points.size());
  std::vector<char> vouched(points.size(), 0);
  {
    const geom::LocalSurface window = coarse.window(comm, points, reach);
    if (!window.mesh.triangles.empty()) {
      const geom::AabbTree tree(window.mesh);
      // A little inside the reach, so round-off in |t| |n| cannot vouch for a farther hit.
      const double vouched_distance = reach * (1.0 - 1e-9);
#pragma omp parallel for schedule(static)
      for (std::int64_t i = 0; i < std::int64_t(points.size()); ++i) {
        const auto I = std::size_t(i);
        const auto hit = tree.nearest_line_crossing(points[I], normals[I]);
        if (!hit || std::abs(hit->t) * normals[I].norm() >= vouched_distance)
          continue;
        const geom::Triangle& local = window.mesh.triangles[std::size_t(hit->triangle)];
        const auto& p = window.mesh.positions;
        parents[I] = parent_face(
            points[I], normals[I], hit->t, window.triangle_ids[std::size_t(hit->triangle)],
            {window.vertex_ids[std::size_t(local[0])], window.vertex_ids[std::size_t(local[1])],
             window.vertex_ids[std::size_t(local[2])]},
            {p[std::size_t(local[0])], p[std::size_t(local[1])], p[std::size_t(local[2])]});
        vouched[I] = 1;
      }
    }
  }
  std::vector<OpenQuery> open;
  for (std::size_t i = 0; i < points.size(); ++i)
    if (!vouched[i])
      open.push_back({{points[i].x(), points[i].y(), points[i].z()},
                      {normals[i].x(), normals[i].y(), normals[i].z()},
                      comm.rank,
                      std::int32_t(i)});
  const std::vector<OpenQuery> every_open = par::allgather_records(comm, open);
  if (every_open.empty())
    return parents;

  std::vector<std::vector<ShareCrossing>> answers(std::size_t(comm.size));
  if (coarse.owned_count() > 0) {
    const geom::AabbTree tree(coarse.owned_surface().mesh);
    for (const OpenQuery& query : every_open) {
      const geom::Vec3 origin(query.origin[0], query.origin[1], query.origin[2]);
      const geom::Vec3 direction(query.direction[0], query.direction[1], query.direction[2]);
      if (const auto hit = tree.nearest_line_crossing(origin, direction))
        answers[std::size_t(query.rank)].push_back(
            {coarse.owned_record(std::size_t(hit->triangle)), hit->t, query.index});
    }
  }
  // Per open point, the nearest crossing over the ranks' shares: AabbTree's order.
  std::vector<const ShareCrossing*> nearest(points.size(), nullptr);
  const std::vector<ShareCrossing> received = par::exchange_records(comm, std::move(answers));
  for (const ShareCrossing& answer : received) {
    const ShareCrossing*& best = nearest[std::size_t(answer.index)];
    const double abs_t = std::abs(answer.t);
    if (best == nullptr || abs_t < std::abs(best->t) ||
        (abs_t == std::abs(best->t) && answer.triangle.id < best->triangle.id))
      best = &answer;
  }
  for (std::size_t i = 0; i < points.size(); ++i) {
    const ShareCrossing* best = nearest[i];
    if (best == nullptr)
      continue; // the line misses the whole level
    const auto& c = best->triangle.corners;
    parents[i] = parent_face(
        points[i], normals[i], best->t, best->triangle.id, best->triangle.vertex,
        {geom::Vec3(c[0], c[1], c[2]), geom::Vec3(c[3], c[4], c[5]), geom::Vec3(c[6], c[7], c[8])});
  }
  return parents;
}

std::vector<ParentFace> find_parent_faces(const par::Comm& comm, const RetiledLevel& level,
                                          const RetiledLevel& coarser) {
  return find_parent_faces(comm, level.positions, level.normals, coarser.triangles,
                           parent_window_reach(coarser.spacing));
}

} // namespace texsim::pipelines::surface_synthesis
