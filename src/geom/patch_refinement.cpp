#include "geom/patch_refinement.hpp"

#include "core/error.hpp"
#include "geom/mesh_topology.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <numeric>

namespace texsim::geom {
namespace {

/// Lattice weights of a point on a coarse triangle's three corners (they sum to the resolution).
using Weights = std::array<std::int64_t, 3>;

Weights operator+(const Weights& a, const Weights& b) {
  return {a[0] + b[0], a[1] + b[1], a[2] + b[2]};
}

/// The hierarchical id of a lattice point of a patch triangle (see the header).
class HierarchicalIds {
public:
  HierarchicalIds(const CoarsePatch& patch, int rounds)
      : patch_(patch), n_(std::int64_t{1} << rounds),
        interior_begin_(patch.coarse_vertices + patch.coarse_edges * (n_ - 1)) {}

  /// Id of the point of weights `w` (summing to `resolution`) on local coarse triangle t.
  std::int64_t id(std::int32_t t, const Weights& w, std::int64_t resolution) const {
    const std::int64_t scale = n_ / resolution;
    const Weights fine = {w[0] * scale, w[1] * scale, w[2] * scale};
    const auto& corners = patch_.mesh.triangles[t];
    for (int c = 0; c < 3; ++c)
      if (fine[c] == n_)
        return patch_.vertex_id[corners[c]];
    for (int c = 0; c < 3; ++c)
      if (fine[c] == 0) { // on the edge opposite corner c
        const int a = (c + 1) % 3, b = (c + 2) % 3;
        // Steps from the edge's vertex of smaller id: the other end's weight.
        const std::int64_t steps =
            patch_.vertex_id[corners[a]] < patch_.vertex_id[corners[b]] ? fine[b] : fine[a];
        return patch_.coarse_vertices + patch_.triangle_edge_id[t][c] * (n_ - 1) + steps - 1;
      }
    const std::int64_t i = fine[0], j = fine[1];
    const std::int64_t per_triangle = (n_ - 1) * (n_ - 2) / 2;
    return interior_begin_ + patch_.triangle_id[t] * per_triangle + (i - 1) * (n_ - 1) -
           (i - 1) * i / 2 + (j - 1);
  }

private:
  const CoarsePatch& patch_;
  std::int64_t n_;
  std::int64_t interior_begin_;
};

/// The patch after some rounds: its mesh, ids, and each triangle's coarse parent and the lattice
/// weights of its corners at the current resolution.
struct Level {
  TriangleMesh mesh;
  std::vector<std::int64_t> id;
  std::vector<std::int32_t> parent;
  std::vector<std::array<Weights, 3>> corner_weights;
  std::vector<EdgeFlags> crease; ///< per triangle; empty: no creases
  std::int64_t resolution = 1;
};

/// A vertex's sharp edges: the boundary and crease edges at it, as the far ends.
struct SharpEdges {
  std::vector<std::int32_t> ends;
  bool on_boundary = false;
};

/// Loop's new position of an old vertex. On two sharp edges (a boundary or a crease) the
/// B-spline mask (6 v + b1 + b2) / 8 along them; on three or more (a corner) it stays; otherwise
/// (a dart too) the interior mask (1 - c) v + c / k sum of the k neighbours, c = 5/8 - (3 + 2
/// cos(2 pi / k))^2 / 64. A boundary vertex with one boundary edge (only at a patch's border, the
/// input being edge-manifold) keeps its position. `neighbours` is scratch, reused across vertices.
Vec3 loop_even(const Level& level, const MeshTopology& topology, std::int32_t v,
               const SharpEdges& sharp, std::vector<std::int32_t>& neighbours) {
  const auto& p = level.mesh.positions;
  const auto by_id = [&](std::int32_t a, std::int32_t b) { return level.id[a] < level.id[b]; };
  if (sharp.ends.size() == 2) {
    const auto [first, second] = std::minmax(sharp.ends[0], sharp.ends[1], by_id);
    return (6.0 * p[v] + p[first] + p[second]) / 8.0;
  }
  if (sharp.ends.size() >= 3 || sharp.on_boundary)
    return p[v];
  const auto row = topology.vertex_neighbors().row(v);
  if (row.empty())
    return p[v];
  neighbours.assign(row.begin(), row.end());
  std::sort(neighbours.begin(), neighbours.end(), by_id);
  Vec3 sum = Vec3::Zero();
  for (const std::int32_t w : neighbours)
    sum += p[w];
  const double k = double(neighbours.size());
  const double spread = 3.0 + 2.0 * std::cos(2.0 * std::numbers::pi / k);
  const double c = 5.0 / 8.0 - spread * spread / 64.0;
  return (1.0 - c) * p[v] + (c / k) * sum;
}

/// Position of the new vertex on edge e: Loop's (3 (a + b) + c + d) / 8 (c, d opposite the edge)
/// or the midpoint on a boundary or crease; the sphere rule's projected midpoint.
Vec3 odd_position(const Level& level, const MeshTopology& topology, std::int32_t e, bool crease,
                  const RefinementStep& step) {
  const auto& p = level.mesh.positions;
  auto [a, b] = topology.edges()[e];
  if (level.id[b] < level.id[a])
    std::swap(a, b);
  if (step.rule == RefinementStep::Rule::kSphere) {
    const Vec3 centre(step.centre[0], step.centre[1], step.centre[2]);
    return centre + step.radius * (0.5 * (p[a] + p[b]) - centre).normalized();
  }
  const auto around = topology.edge_triangles(e);
  if (around.size() == 1 || crease)
    return 0.5 * (p[a] + p[b]);
  std::array<std::int32_t, 2> opposite{};
  for (int k = 0; k < 2; ++k)
    for (const std::int32_t corner : level.mesh.triangles[around[k]])
      if (corner != a && corner != b)
        opposite[k] = corner;
  if (level.id[opposite[1]] < level.id[opposite[0]])
    std::swap(opposite[0], opposite[1]);
  return (3.0 * (p[a] + p[b]) + p[opposite[0]] + p[opposite[1]]) / 8.0;
}

Level refine_once(const Level& level, const RefinementStep& step, const HierarchicalIds& ids) {
  const MeshTopology topology(level.mesh);
  TEXSIM_VERIFY(
      topology.non_manifold_edges().empty(),
      "refine_patch: " << topology.non_manifold_edges().size()
                       << " edges are shared by more than two triangles; repair the mesh");
  const std::int32_t vertices = level.mesh.num_vertices();
  const std::int32_t edges = topology.num_edges();
  Level fine;
  fine.resolution = 2 * level.resolution;
  fine.mesh.positions.resize(std::size_t(vertices) + std::size_t(edges));
  fine.id.resize(fine.mesh.positions.size(), -1);
  std::copy(level.id.begin(), level.id.end(), fine.id.begin());

  const std::vector<char> crease = edge_flags(topology, level.crease);
  std::vector<SharpEdges> sharp(static_cast<std::size_t>(vertices));
  for (std::int32_t e = 0; e < edges; ++e) {
    const bool boundary = topology.edge_triangles(e).size() == 1;
    if (!boundary && !crease[e])
      continue;
    const auto [a, b] = topology.edges()[e];
    sharp[a].ends.push_back(b);
    sharp[b].ends.push_back(a);
    sharp[a].on_boundary = sharp[a].on_boundary || boundary;
    sharp[b].on_boundary = sharp[b].on_boundary || boundary;
  }
  std::vector<std::int32_t> neighbours;
  for (std::int32_t v = 0; v < vertices; ++v)
    fine.mesh.positions[v] = step.rule == RefinementStep::Rule::kLoop
                                 ? loop_even(level, topology, v, sharp[v], neighbours)
                                 : level.mesh.positions[v];
  for (std::int32_t e = 0; e < edges; ++e)
    fine.mesh.positions[vertices + e] = odd_position(level, topology, e, crease[e] != 0, step);

  const std::size_t triangles = level.mesh.triangles.size();
  fine.mesh.triangles.reserve(4 * triangles);
  fine.parent.reserve(4 * triangles);
  fine.corner_weights.reserve(4 * triangles);
  if (!level.crease.empty())
    fine.crease.reserve(4 * triangles);
  for (std::size_t t = 0; t < triangles; ++t) {
    const auto& corner = level.mesh.triangles[t];
    const auto& w = level.corner_weights[t];
    const Weights doubled[3] = {w[0] + w[0], w[1] + w[1], w[2] + w[2]};
    // mid[i] sits on the side opposite corner i, weights the sum of that side's ends.
    const Weights mid_weights[3] = {w[1] + w[2], w[2] + w[0], w[0] + w[1]};
    std::array<std::int32_t, 3> mid{};
    for (int i = 0; i < 3; ++i) {
      mid[i] = vertices + topology.triangle_edges(std::int32_t(t))[i];
      if (fine.id[mid[i]] < 0)
        fine.id[mid[i]] = ids.id(level.parent[t], mid_weights[i], fine.resolution);
    }
    fine.mesh.triangles.push_back({corner[0], mid[2], mid[1]});
    fine.corner_weights.push_back({doubled[0], mid_weights[2], mid_weights[1]});
    fine.mesh.triangles.push_back({corner[1], mid[0], mid[2]});
    fine.corner_weights.push_back({doubled[1], mid_weights[0], mid_weights[2]});
    fine.mesh.triangles.push_back({corner[2], mid[1], mid[0]});
    fine.corner_weights.push_back({doubled[2], mid_weights[1], mid_weights[0]});
    fine.mesh.triangles.push_back({mid[0], mid[1], mid[2]});
    fine.corner_weights.push_back({mid_weights[0], mid_weights[1], mid_weights[2]});
    for (int child = 0; child < 4; ++child)
      fine.parent.push_back(level.parent[t]);
    if (!level.crease.empty()) {
      // A corner child's edges along the sides are halves of them; the middle child's are new.
      const EdgeFlags& side = level.crease[t];
      fine.crease.push_back({0, side[1], side[2]});
      fine.crease.push_back({0, side[2], side[0]});
      fine.crease.push_back({0, side[0], side[1]});
      fine.crease.push_back({0, 0, 0});
    }
  }
  return fine;
}

} // namespace

std::vector<EdgeFlags> triangle_edge_flags(const MeshTopology& topology,
                                           std::span<const char> edge_flags) {
  if (edge_flags.empty())
    return {};
  TEXSIM_VERIFY(edge_flags.size() == std::size_t(topology.num_edges()),
                "triangle_edge_flags: " << edge_flags.size() << " flags for "
                                        << topology.num_edges() << " edges");
  std::vector<EdgeFlags> flags(std::size_t(topology.num_triangles()));
  for (std::int32_t t = 0; t < topology.num_triangles(); ++t)
    for (int i = 0; i < 3; ++i)
      flags[t][i] = edge_flags[std::size_t(topology.triangle_edges(t)[i])];
  return flags;
}

std::vector<char> edge_flags(const MeshTopology& topology,
                             std::span<const EdgeFlags> triangle_flags) {
  std::vector<char> flags(std::size_t(topology.num_edges()), 0);
  for (std::size_t t = 0; t < triangle_flags.size(); ++t)
    for (int i = 0; i < 3; ++i)
      if (triangle_flags[t][i])
        flags[std::size_t(topology.triangle_edges(std::int32_t(t))[i])] = 1;
  return flags;
}

CoarsePatch CoarsePatch::whole(const TriangleMesh& mesh, std::span<const char> creases) {
  const MeshTopology topology(mesh);
  CoarsePatch patch;
  patch.mesh = mesh;
  patch.vertex_id.resize(mesh.positions.size());
  std::iota(patch.vertex_id.begin(), patch.vertex_id.end(), 0);
  patch.triangle_id.resize(mesh.triangles.size());
  std::iota(patch.triangle_id.begin(), patch.triangle_id.end(), 0);
  for (std::int32_t t = 0; t < mesh.num_triangles(); ++t) {
    const auto& edges = topology.triangle_edges(t);
    patch.triangle_edge_id.push_back({edges[0], edges[1], edges[2]});
  }
  patch.triangle_edge_crease = triangle_edge_flags(topology, creases);
  patch.coarse_vertices = mesh.num_vertices();
  patch.coarse_edges = topology.num_edges();
  return patch;
}

PatchCutter::PatchCutter(const TriangleMesh& mesh, const MeshTopology& topology,
                         std::span<const char> creases)
    : mesh_(mesh), topology_(topology), creases_(creases),
      triangle_stamp_(mesh.triangles.size(), -1), vertex_stamp_(mesh.positions.size(), -1),
      local_of_(mesh.positions.size(), -1) {}

CoarsePatch PatchCutter::cut(std::span<const std::int32_t> seeds, int rings,
                             std::vector<std::int32_t>* ring_of) {
  const int stamp = cut_count_++;
  std::vector<std::int32_t> triangles(seeds.begin(), seeds.end());
  std::vector<std::int32_t> ring(triangles.size(), 0);
  for (const std::int32_t t : triangles)
    triangle_stamp_[t] = stamp;
  std::size_t ring_begin = 0;
  for (int r = 1; r <= rings; ++r) {
    const std::size_t ring_end = triangles.size();
    for (std::size_t k = ring_begin; k < ring_end; ++k)
      for (const std::int32_t v : mesh_.triangles[triangles[k]]) {
        if (vertex_stamp_[v] == stamp)
          continue;
        vertex_stamp_[v] = stamp;
        for (const std::int32_t t : topology_.vertex_triangles().row(v))
          if (triangle_stamp_[t] != stamp) {
            triangle_stamp_[t] = stamp;
            triangles.push_back(t);
            ring.push_back(r);
          }
      }
    ring_begin = ring_end;
  }
  std::vector<std::size_t> order(triangles.size());
  std::iota(order.begin(), order.end(), 0);
  std::sort(order.begin(), order.end(),
            [&](std::size_t a, std::size_t b) { return triangles[a] < triangles[b]; });
  std::vector<std::int32_t> vertices;
  for (const std::int32_t t : triangles)
    for (const std::int32_t v : mesh_.triangles[t])
      vertices.push_back(v);
  std::sort(vertices.begin(), vertices.end());
  vertices.erase(std::unique(vertices.begin(), vertices.end()), vertices.end());

  CoarsePatch patch;
  patch.coarse_vertices = mesh_.num_vertices();
  patch.coarse_edges = topology_.num_edges();
  for (std::size_t local = 0; local < vertices.size(); ++local) {
    local_of_[vertices[local]] = std::int32_t(local);
    patch.mesh.positions.push_back(mesh_.positions[vertices[local]]);
    patch.vertex_id.push_back(vertices[local]);
  }
  if (ring_of != nullptr)
    ring_of->clear();
  for (const std::size_t k : order) {
    const std::int32_t t = triangles[k];
    const auto& tri = mesh_.triangles[t];
    patch.mesh.triangles.push_back({local_of_[tri[0]], local_of_[tri[1]], local_of_[tri[2]]});
    patch.triangle_id.push_back(t);
    const auto& edges = topology_.triangle_edges(t);
    patch.triangle_edge_id.push_back({edges[0], edges[1], edges[2]});
    if (!creases_.empty())
      patch.triangle_edge_crease.push_back({creases_[std::size_t(edges[0])],
                                            creases_[std::size_t(edges[1])],
                                            creases_[std::size_t(edges[2])]});
    if (ring_of != nullptr)
      ring_of->push_back(ring[k]);
  }
  return patch;
}

std::int64_t refined_vertex_count(std::int64_t vertices, std::int64_t edges, std::int64_t triangles,
                                  int rounds) {
  const std::int64_t n = std::int64_t{1} << rounds;
  return vertices + edges * (n - 1) + triangles * ((n - 1) * (n - 2) / 2);
}

RefinedPatch refine_patch(const CoarsePatch& patch, std::span<const RefinementStep> steps) {
  TEXSIM_VERIFY(steps.size() <= 20, "refine_patch: " << steps.size() << " rounds is too many");
  const HierarchicalIds ids(patch, int(steps.size()));
  Level level;
  level.mesh = patch.mesh;
  level.id = patch.vertex_id;
  level.parent.resize(patch.mesh.triangles.size());
  std::iota(level.parent.begin(), level.parent.end(), 0);
  level.corner_weights.assign(patch.mesh.triangles.size(),
                              {Weights{1, 0, 0}, Weights{0, 1, 0}, Weights{0, 0, 1}});
  level.crease = patch.triangle_edge_crease;
  for (const auto& step : steps)
    level = refine_once(level, step, ids);
  return {std::move(level.mesh), std::move(level.id), std::move(level.parent),
          std::move(level.crease)};
}

TriangleMesh refine(const TriangleMesh& mesh, std::span<const RefinementStep> steps,
                    std::span<const char> creases, std::vector<char>* fine_creases) {
  if (steps.empty()) {
    if (fine_creases != nullptr)
      fine_creases->assign(creases.begin(), creases.end());
    return mesh;
  }
  const auto patch = CoarsePatch::whole(mesh, creases);
  const auto refined = refine_patch(patch, steps);
  const std::int64_t count = refined_vertex_count(patch.coarse_vertices, patch.coarse_edges,
                                                  mesh.num_triangles(), int(steps.size()));
  TEXSIM_VERIFY(std::int64_t(refined.vertex_id.size()) == count && count < INT32_MAX,
                "refine: " << refined.vertex_id.size() << " vertices, expected " << count);
  TriangleMesh out;
  out.positions.resize(std::size_t(count));
  for (std::size_t v = 0; v < refined.vertex_id.size(); ++v)
    out.positions[std::size_t(refined.vertex_id[v])] = refined.mesh.positions[v];
  out.triangles = refined.mesh.triangles;
  for (auto& triangle : out.triangles)
    for (auto& v : triangle)
      v = std::int32_t(refined.vertex_id[v]);
  if (fine_creases != nullptr)
    *fine_creases = refined.triangle_edge_crease.empty()
                        ? std::vector<char>()
                        : edge_flags(MeshTopology(out), refined.triangle_edge_crease);
  return out;
}

} // namespace texsim::geom
