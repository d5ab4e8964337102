#include "geom/split_surface_sampler.hpp"

#include "core/error.hpp"
#include "geom/aabb_tree.hpp"
#include "geom/mesh_measures.hpp"
#include "par/record_exchange.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>

namespace texsim::geom {
namespace {

/// A share's bounding box, lo xyz then hi xyz (lo > hi when the share is empty), grown by a
/// billionth of its largest coordinate: a triangle's projected point may fall outside its
/// corners' box by round-off, never by that much.
using ShareBox = std::array<double, 6>;

ShareBox share_box(const TriangleMesh& share) {
  constexpr double kInf = std::numeric_limits<double>::infinity();
  ShareBox box{kInf, kInf, kInf, -kInf, -kInf, -kInf};
  for (const auto& t : share.triangles)
    for (const auto v : t)
      for (int axis = 0; axis < 3; ++axis) {
        box[std::size_t(axis)] = std::min(box[std::size_t(axis)], share.positions[v][axis]);
        box[std::size_t(axis) + 3] = std::max(box[std::size_t(axis) + 3], share.positions[v][axis]);
      }
  if (share.triangles.empty())
    return box;
  double scale = 0.0;
  for (const double bound : box)
    scale = std::max(scale, std::abs(bound));
  const double pad = 1e-9 * scale + std::numeric_limits<double>::min();
  for (int axis = 0; axis < 3; ++axis) {
    box[std::size_t(axis)] -= pad;
    box[std::size_t(axis) + 3] += pad;
  }
  return box;
}

bool is_empty(const ShareBox& box) {
  return box[0] > box[3];
}

/// Squared distance from `p` to the box (0 inside).
double squared_distance_to(const ShareBox& box, const Vec3& p) {
  double squared = 0.0;
  for (int axis = 0; axis < 3; ++axis) {
    const double gap =
        std::max({box[std::size_t(axis)] - p[axis], p[axis] - box[std::size_t(axis) + 3], 0.0});
    squared += gap * gap;
  }
  return squared;
}

struct Query {
  std::int64_t point = 0; ///< index in rank 0's points
  std::array<double, 3> xyz{};
};

struct Answer {
  std::int64_t point = 0;
  std::int64_t triangle = -1; ///< id in the whole surface
  double squared_distance = std::numeric_limits<double>::infinity();
  std::array<double, 3> value{};
};

/// AabbTree::nearest_triangle's rule across shares.
bool nearer(const Answer& a, const Answer& b) {
  return a.squared_distance < b.squared_distance ||
         (a.squared_distance == b.squared_distance && a.triangle < b.triangle);
}

/// This rank's answers to the queries sent to it, in their order (sent back to rank 0).
std::vector<Answer> answer(const TriangleMesh& share, std::span<const std::int64_t> triangle_ids,
                           std::span<const std::array<double, 3>> values,
                           const std::optional<AabbTree>& tree, std::span<const Query> queries) {
  std::vector<Answer> answers(queries.size());
#pragma omp parallel for schedule(static)
  for (std::size_t q = 0; q < queries.size(); ++q) {
    const Vec3 p(queries[q].xyz[0], queries[q].xyz[1], queries[q].xyz[2]);
    const auto nearest = tree->nearest_triangle(p);
    const auto& t = share.triangles[std::size_t(nearest.triangle)];
    const auto w = barycentric_weights(share.positions[t[0]], share.positions[t[1]],
                                       share.positions[t[2]], nearest.point);
    Answer& a = answers[q];
    a.point = queries[q].point;
    a.triangle = triangle_ids[std::size_t(nearest.triangle)];
    a.squared_distance = nearest.squared_distance;
    for (std::size_t k = 0; k < 3; ++k)
      a.value[k] = w[0] * values[std::size_t(t[0])][k] + w[1] * values[std::size_t(t[1])][k] +
                   w[2] * values[std::size_t(t[2])][k];
  }
  return answers;
}

} // namespace

std::vector<std::array<double, 3>>
sample_split_surface(const par::Comm& comm, const TriangleMesh& share,
                     std::span<const std::int64_t> triangle_ids,
                     std::span<const std::array<double, 3>> values, std::span<const Vec3> points) {
  TEXSIM_VERIFY(
      triangle_ids.size() == share.triangles.size() && values.size() == share.positions.size(),
      "sample_split_surface: " << triangle_ids.size() << " ids for " << share.triangles.size()
                               << " triangles, " << values.size() << " values for "
                               << share.positions.size() << " vertices");
  const auto boxes = par::allgather_records(comm, std::vector<ShareBox>{share_box(share)});
  if (std::all_of(boxes.begin(), boxes.end(), is_empty))
    throw Error("sample_split_surface: no rank holds a triangle");
  std::optional<AabbTree> tree;
  if (!share.triangles.empty())
    tree.emplace(share);

  // One round: rank 0's queries out, every rank's answers back to rank 0.
  const auto ask = [&](std::vector<std::vector<Query>> queries) {
    const auto mine = par::exchange_records(comm, std::move(queries));
    std::vector<std::vector<Answer>> back(std::size_t(comm.size));
    back[0] = answer(share, triangle_ids, values, tree, mine);
    return par::exchange_records(comm, std::move(back));
  };
  const auto query_of = [&](std::size_t i) {
    return Query{std::int64_t(i), {points[i].x(), points[i].y(), points[i].z()}};
  };

  // Round 1: each point to the rank whose box is nearest (the lowest such rank; a point no box is
  // nearer than infinity to, a non-finite one, to the first rank with triangles).
  const auto holder =
      std::int32_t(std::find_if_not(boxes.begin(), boxes.end(), is_empty) - boxes.begin());
  std::vector<std::int32_t> first_rank(points.size(), holder);
  std::vector<std::vector<Query>> queries(std::size_t(comm.size));
  for (std::size_t i = 0; i < points.size(); ++i) {
    double nearest = std::numeric_limits<double>::infinity();
    for (std::size_t r = 0; r < boxes.size(); ++r) {
      const double squared =
          is_empty(boxes[r]) ? nearest : squared_distance_to(boxes[r], points[i]);
      if (squared < nearest) {
        nearest = squared;
        first_rank[i] = std::int32_t(r);
      }
    }
    queries[std::size_t(first_rank[i])].push_back(query_of(i));
  }
  std::vector<Answer> best(points.size());
  for (const auto& a : ask(std::move(queries)))
    best[std::size_t(a.point)] = a;

  // Round 2: each point to every other rank whose box is no farther than its answer so far (a
  // triangle as near, or as near with a smaller id, lies inside its rank's box).
  queries.assign(std::size_t(comm.size), {});
  for (std::size_t i = 0; i < points.size(); ++i)
    for (std::size_t r = 0; r < boxes.size(); ++r)
      if (std::int32_t(r) != first_rank[i] && !is_empty(boxes[r]) &&
          squared_distance_to(boxes[r], points[i]) <= best[i].squared_distance)
        queries[r].push_back(query_of(i));
  for (const auto& a : ask(std::move(queries)))
    if (nearer(a, best[std::size_t(a.point)]))
      best[std::size_t(a.point)] = a;

  std::vector<std::array<double, 3>> result;
  result.reserve(best.size());
  for (const auto& a : best)
    result.push_back(a.value);
  return result;
}

} // namespace texsim::geom
