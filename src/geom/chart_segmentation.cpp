#include "geom/chart_segmentation.hpp"

#include "core/error.hpp"
#include "geom/graph_regions.hpp"
#include "geom/submesh.hpp"

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <functional>
#include <numbers>
#include <queue>
#include <tuple>

namespace texsim::geom {
namespace {

constexpr std::int32_t kFree = -1;    ///< still to be put in a chart
constexpr std::int32_t kOutside = -2; ///< not part of the triangles being cut

Vec3 centroid(const TriangleMesh& mesh, std::int32_t t) {
  const auto& tri = mesh.triangles[t];
  return (mesh.positions[tri[0]] + mesh.positions[tri[1]] + mesh.positions[tri[2]]) / 3.0;
}

Vec3 unit_normal(const TriangleMesh& mesh, std::int32_t t) {
  const auto& tri = mesh.triangles[t];
  const Vec3 n = (mesh.positions[tri[1]] - mesh.positions[tri[0]])
                     .cross(mesh.positions[tri[2]] - mesh.positions[tri[0]]);
  const double length = n.norm();
  return length > 0.0 ? Vec3(n / length) : Vec3::Zero();
}

/// A triangle offered to a chart, at its centroid's distance from the chart's seed.
struct Candidate {
  double cost;
  std::int32_t triangle;
  std::int32_t chart;
};

/// Orders the priority queue so that the smallest (cost, triangle, chart) comes out first.
struct ComesLater {
  bool operator()(const Candidate& a, const Candidate& b) const {
    return std::tie(a.cost, a.triangle, a.chart) > std::tie(b.cost, b.triangle, b.chart);
  }
};

/// Grows disk-shaped charts over the triangles labelled kFree in `chart_of`, several at once if
/// several are seeded, best candidate first. A chart grown only under the disk rule from one
/// triangle stays a disk: gluing a triangle along one edge (third vertex new) or along two
/// consecutive boundary edges glues a disk to a disk along an arc.
class DiskGrower {
public:
  /// The allowed(triangle, chart) test every accepted triangle must also pass.
  using Admission = std::function<bool(std::int32_t, std::int32_t)>;

  DiskGrower(const TriangleMesh& mesh, const MeshTopology& topology,
             std::vector<std::int32_t>& chart_of)
      : mesh_(mesh), topology_(topology), chart_of_(chart_of) {}

  /// Starts a new chart at the free triangle `seed`; returns its id (0, 1, ... in seeding order).
  std::int32_t seed(std::int32_t seed) {
    const auto chart = static_cast<std::int32_t>(seeds_.size());
    seeds_.push_back(seed);
    sizes_.push_back(0);
    add(seed, chart);
    return chart;
  }

  /// Grows the seeded charts until no free neighbour passes `allowed` and the disk rule.
  void grow(const Admission& allowed) {
    while (!queue_.empty()) {
      const Candidate next = queue_.top();
      queue_.pop();
      if (chart_of_[next.triangle] == kFree && allowed(next.triangle, next.chart) &&
          keeps_disk(next.triangle, next.chart)) {
        add(next.triangle, next.chart);
      }
    }
  }

  std::int32_t seed_of(std::int32_t chart) const { return seeds_[chart]; }
  std::int32_t size_of(std::int32_t chart) const { return sizes_[chart]; }

private:
  /// The triangle across edge `side` (opposite corner `side`) of t, or -1 on a boundary or a
  /// non-manifold edge.
  std::int32_t across(std::int32_t t, int side) const {
    const auto triangles = topology_.edge_triangles(topology_.triangle_edges(t)[side]);
    if (triangles.size() != 2) {
      return -1;
    }
    return triangles[0] == t ? triangles[1] : triangles[0];
  }

  bool touches(std::int32_t vertex, std::int32_t chart) const {
    const auto around = topology_.vertex_triangles().row(vertex);
    return std::any_of(around.begin(), around.end(),
                       [&](std::int32_t t) { return chart_of_[t] == chart; });
  }

  bool keeps_disk(std::int32_t t, std::int32_t chart) const {
    int shared = 0;
    int shared_side = -1;
    for (int side = 0; side < 3; ++side) {
      const std::int32_t other = across(t, side);
      if (other >= 0 && chart_of_[other] == chart) {
        ++shared;
        shared_side = side;
      }
    }
    if (shared == 1) {
      // Corner `shared_side` is opposite the shared edge: touching the chart there would pinch it.
      return !touches(mesh_.triangles[t][shared_side], chart);
    }
    return shared == 2; // three shared edges would close the chart into a sphere
  }

  void add(std::int32_t t, std::int32_t chart) {
    chart_of_[t] = chart;
    ++sizes_[chart];
    const Vec3 origin = centroid(mesh_, seeds_[chart]);
    for (int side = 0; side < 3; ++side) {
      const std::int32_t other = across(t, side);
      if (other >= 0 && chart_of_[other] == kFree) {
        queue_.push({(centroid(mesh_, other) - origin).norm(), other, chart});
      }
    }
  }

  const TriangleMesh& mesh_;
  const MeshTopology& topology_;
  std::vector<std::int32_t>& chart_of_;
  std::vector<std::int32_t> seeds_;
  std::vector<std::int32_t> sizes_;
  std::priority_queue<Candidate, std::vector<Candidate>, ComesLater> queue_;
};

/// Lowest-id free triangle at or after `from`, or the triangle count when none is left.
std::int32_t next_free(const std::vector<std::int32_t>& chart_of, std::int32_t from) {
  while (from < static_cast<std::int32_t>(chart_of.size()) && chart_of[from] != kFree) {
    ++from;
  }
  return from;
}

/// Triangle lists of labels 0 .. count-1, each in increasing id order.
std::vector<std::vector<std::int32_t>> members(const std::vector<std::int32_t>& chart_of,
                                               std::int32_t count) {
  std::vector<std::vector<std::int32_t>> charts(count);
  for (std::int32_t t = 0; t < static_cast<std::int32_t>(chart_of.size()); ++t) {
    if (chart_of[t] >= 0) {
      charts[chart_of[t]].push_back(t);
    }
  }
  return charts;
}

/// Appends `chart` to `out` if it is a disk, else its split_chart() pieces, recursively.
void append_disks(const TriangleMesh& mesh, const MeshTopology& topology,
                  std::vector<std::int32_t> chart, std::vector<std::vector<std::int32_t>>& out) {
  if (chart.size() == 1 || is_topological_disk(mesh, chart)) {
    out.push_back(std::move(chart));
    return;
  }
  for (auto& piece : split_chart(mesh, topology, chart)) {
    append_disks(mesh, topology, std::move(piece), out);
  }
}

} // namespace

ChartSegmentation segment_charts(const TriangleMesh& mesh, const ChartSettings& settings) {
  TEXSIM_VERIFY(settings.max_chart_triangles >= 1,
                "segment_charts: max_chart_triangles must be >= 1, got "
                    << settings.max_chart_triangles);
  TEXSIM_VERIFY(settings.max_normal_deviation_degrees > 0.0 &&
                    settings.max_normal_deviation_degrees <= 180.0,
                "segment_charts: max_normal_deviation_degrees must be in (0, 180], got "
                    << settings.max_normal_deviation_degrees);
  const MeshTopology topology(mesh);
  const double min_cosine =
      std::cos(settings.max_normal_deviation_degrees * std::numbers::pi / 180.0);

  std::vector<std::int32_t> chart_of(mesh.triangles.size(), kFree);
  DiskGrower grower(mesh, topology, chart_of);
  std::int32_t count = 0;
  for (std::int32_t seed = next_free(chart_of, 0); seed < mesh.num_triangles();
       seed = next_free(chart_of, seed)) {
    const std::int32_t chart = grower.seed(seed);
    const Vec3 seed_normal = unit_normal(mesh, seed);
    grower.grow([&](std::int32_t t, std::int32_t c) {
      return grower.size_of(c) < settings.max_chart_triangles &&
             unit_normal(mesh, t).dot(seed_normal) >= min_cosine;
    });
    count = chart + 1;
  }

  std::vector<std::vector<std::int32_t>> disks;
  for (auto& chart : members(chart_of, count)) {
    append_disks(mesh, topology, std::move(chart), disks);
  }
  std::sort(disks.begin(), disks.end(),
            [](const auto& a, const auto& b) { return a.front() < b.front(); });

  ChartSegmentation result;
  result.chart_of_triangle.assign(mesh.triangles.size(), kFree);
  result.chart_count = static_cast<std::int32_t>(disks.size());
  for (std::int32_t c = 0; c < result.chart_count; ++c) {
    for (const std::int32_t t : disks[c]) {
      result.chart_of_triangle[t] = c;
    }
  }
  return result;
}

std::vector<std::vector<std::int32_t>> split_chart(const TriangleMesh& mesh,
                                                   const MeshTopology& topology,
                                                   std::span<const std::int32_t> chart_triangles) {
  TEXSIM_VERIFY(chart_triangles.size() >= 2, "split_chart: a chart of "
                                                 << chart_triangles.size()
                                                 << " triangles cannot be split");
  std::vector<std::int32_t> chart_of(mesh.triangles.size(), kOutside);
  for (const std::int32_t t : chart_triangles) {
    chart_of[t] = kFree;
  }
  // The two seeds: farthest from the lowest-id triangle, then farthest from that (ties: lower id).
  const auto farthest_from = [&](std::int32_t from) {
    const Vec3 origin = centroid(mesh, from);
    std::int32_t best = -1;
    double best_distance = -1.0;
    for (std::int32_t t = 0; t < mesh.num_triangles(); ++t) {
      if (chart_of[t] == kFree) {
        const double distance = (centroid(mesh, t) - origin).squaredNorm();
        if (distance > best_distance) {
          best_distance = distance;
          best = t;
        }
      }
    }
    return best;
  };
  const std::int32_t lowest = next_free(chart_of, 0);
  const std::int32_t first = farthest_from(lowest);
  std::int32_t second = farthest_from(first);
  if (second == first) { // all centroids coincide
    second = first == lowest ? next_free(chart_of, lowest + 1) : lowest;
  }

  DiskGrower grower(mesh, topology, chart_of);
  const auto anything = [](std::int32_t, std::int32_t) { return true; };
  grower.seed(first);
  std::int32_t count = grower.seed(second) + 1;
  grower.grow(anything);
  for (std::int32_t seed = next_free(chart_of, 0); seed < mesh.num_triangles();
       seed = next_free(chart_of, seed)) {
    count = grower.seed(seed) + 1;
    grower.grow(anything);
  }
  auto pieces = members(chart_of, count);
  std::sort(pieces.begin(), pieces.end(),
            [](const auto& a, const auto& b) { return a.front() < b.front(); });
  return pieces;
}

bool is_topological_disk(const TriangleMesh& mesh, std::span<const std::int32_t> chart_triangles) {
  if (chart_triangles.empty()) {
    return false;
  }
  const Submesh chart = extract_triangles(mesh, chart_triangles);
  const MeshTopology topology(chart.mesh);
  if (!topology.is_manifold() || topology.is_closed() || topology.euler_characteristic() != 1) {
    return false;
  }
  // Manifold, so vertex-connected means edge-connected.
  const std::vector<char> all(chart.mesh.positions.size(), 1);
  const auto regions = label_regions(topology.vertex_neighbors(), all);
  return std::all_of(regions.begin(), regions.end(), [](std::int32_t r) { return r == 0; });
}

} // namespace texsim::geom
