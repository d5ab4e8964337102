#pragma once
/// Wei and Levoy 2001, section 3.3 (Fig. 5): flatten a patch of the mesh around a vertex and find
/// where the neighbourhood template's samples fall on it. The flattening follows Praun et al.'s
/// lapped textures: seed triangles projected orthographically onto the vertex's (s, t) plane,
/// then neighbouring triangles unfolded about their shared edge in order of increasing distance,
/// growth stopped where the surface folds away from the frame.
#include "geom/mesh_topology.hpp"
#include "geom/triangle_mesh.hpp"

#include <Eigen/Core>

#include <array>
#include <cstdint>
#include <span>
#include <tuple>
#include <vector>

namespace texsim::pipelines::surface_synthesis {

/// Local frame at a vertex: origin on the surface, s (texture right), t = n x s (texture up), n
/// (unit normal). s, t, n must be orthonormal (model units for origin).
struct TangentFrame {
  geom::Vec3 origin, s, t, n;
};

/// Triangles of the patch, their vertex ids and flattened corners (model units; corner i of
/// triangles[k] is vertex vertices[k][i] at corners[k][i]), in the order they were added. A vertex
/// shared by two patch triangles may sit at two places when the patch is not developable: each
/// triangle carries its own corners.
struct FlattenedPatch {
  std::vector<std::int32_t> triangles;
  std::vector<geom::Triangle> vertices;
  std::vector<std::array<Eigen::Vector2d, 3>> corners;
};

/// Where one template sample falls: the patch triangle's three vertex ids and barycentric
/// weights, or uncovered (vertices[0] == -1). The weights are stored as float, like the colours
/// they weigh: a level holds a sample for each of the 64 template points ({7x7,2}) of every owned
/// vertex, the largest block of a rank's memory during synthesis: 24 bytes a sample, not 40.
struct SampleWeights {
  std::array<std::int32_t, 3> vertices{-1, -1, -1};
  std::array<float, 3> weights{};
  bool covered() const { return vertices[0] >= 0; }
};

class PatchScratch;

/// Flattens the patch around frame.origin into `out` (cleared first).
///
/// The seeds (the triangles around p, or p's parent face on the coarser level; repeats ignored)
/// are projected orthographically onto (s, t) about frame.origin. Then triangles across the edges
/// of patch triangles are unfolded about the shared, already flattened edge: a far vertex not yet
/// placed goes on the far side of that edge at its 3D distances from the edge's two ends, so the
/// triangle keeps all three 3D edge lengths whenever the shared edge has its own (every edge not
/// between two seed vertices, which the projection shortens). Every vertex has one place in the
/// patch: a triangle whose three vertices are already placed (where growth fronts meet around a
/// curved region) takes them as they are, so the patch has no cracks, and its edges are stretched
/// or shrunk by the surface's angle deficit instead. On a developable surface every path places a
/// vertex at the same point, and with seeds in the frame's plane the patch is an isometry.
/// Candidates are added in order of increasing distance of their flattened triangle from the
/// origin (ties: lower triangle id, then earlier parent), as long as that distance is <= radius;
/// a candidate whose far vertex was placed meanwhile is judged again at that vertex's place.
///
/// Where growth stops (the paper's "flips"): a triangle whose 3D normal makes 90 degrees or more
/// with frame.n (the surface folds back; its orthographic view would be flipped) is never added,
/// neither as a seed nor by unfolding, and growth does not continue through it. Nor is a triangle
/// whose flattened corners have non-positive signed area: flipped between placed vertices (the
/// patch would overlap itself, e.g. around a saddle), or unfolded through inconsistently oriented
/// neighbours, or a seed projected edge-on. Overlaps that flip no triangle (a surface winding more
/// than a full turn within the radius) are not searched for: sample_patch resolves them by patch
/// order, the nearer triangle first.
///
/// Cost: O(k log k) for a patch of k triangles, no heap allocation once scratch and out have grown
/// to the patch size (the scratch holds marks and a 2D position per vertex and a mark per
/// triangle of the whole mesh, about 24 bytes per vertex, allocated on the first call). Thread-safe
/// for separate scratch and out.
void flatten_patch(const geom::TriangleMesh& mesh, const geom::MeshTopology& topology,
                   std::span<const std::int32_t> seed_triangles, const TangentFrame& frame,
                   double radius, FlattenedPatch& out, PatchScratch& scratch);

/// Each sample position (flattened coordinates, model units) located in the first patch triangle
/// (in patch order) that contains it, with its barycentric weights. Edges are inclusive with a
/// tolerance of 1e-12 in barycentric coordinates (a sample on a grid vertex is found despite
/// rounding); accepted weights are clamped at 0 and renormalised to sum 1. Samples in no
/// triangle are left uncovered. out.size() must equal positions.size(). Cost O(samples x patch).
void sample_patch(const FlattenedPatch& patch, std::span<const Eigen::Vector2d> positions,
                  std::span<SampleWeights> out);

/// Reusable working memory of flatten_patch: per-triangle and per-vertex marks of the current
/// call, the vertices' flattened positions and the candidate heap. One per thread; its contents
/// between calls mean nothing to the caller.
class PatchScratch {
public:
  PatchScratch() = default;

private:
  friend void flatten_patch(const geom::TriangleMesh&, const geom::MeshTopology&,
                            std::span<const std::int32_t>, const TangentFrame&, double,
                            FlattenedPatch&, PatchScratch&);

  /// One way of placing a triangle: reached across an edge of patch triangle `parent`, its
  /// corner `opposite` that edge at far_position (unfolded, or where that vertex already was).
  struct Candidate {
    double distance;
    std::int32_t triangle;
    std::int32_t parent;
    int opposite;
    Eigen::Vector2d far_position;
    /// Order of the min-heap: nearer first, then lower triangle id, then earlier parent.
    auto key() const { return std::tie(distance, triangle, parent); }
  };

  /// triangle_mark[t] == call_id: t is in the patch, or can never join it (it folds away, or
  /// comes out flipped between placed vertices), during this call.
  std::vector<std::uint32_t> triangle_mark;
  /// vertex_mark[v] == call_id: v is placed at vertex_position[v] during this call.
  std::vector<std::uint32_t> vertex_mark;
  std::vector<Eigen::Vector2d> vertex_position;
  std::uint32_t call_id = 0;
  std::vector<Candidate> heap;
};

} // namespace texsim::pipelines::surface_synthesis
