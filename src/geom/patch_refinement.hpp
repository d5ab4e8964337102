#pragma once
/// Rounds of 1-to-4 triangle refinement applied to a patch of a coarse mesh, with vertex ids that
/// do not depend on the patch: the same fine vertex gets the same id and the same position bits
/// whether the whole mesh is refined at once or each rank refines its own patch. This is what lets
/// fem_rd refine a surface on the ranks' parts (DistributedMesh) instead of on rank 0 alone.
///
/// After R rounds (n = 2^R), the fine vertices of a coarse mesh with V vertices, E edges and T
/// triangles are the points of a barycentric lattice of step 1/n on every coarse triangle. Their
/// ids, the hierarchical numbering:
///   coarse vertex v                                  -> v
///   point s steps (1..n-1) along coarse edge e,
///     counted from its vertex of smaller id          -> V + e (n - 1) + s - 1
///   interior point of coarse triangle t with lattice
///     weights (i, j, n - i - j) on its corners        -> V + E (n - 1) + t (n-1)(n-2)/2 + index(i,
///     j)
/// Edge ids are MeshTopology's on the whole coarse mesh.
///
/// Loop rounds (Loop 1987, the masks CGAL's Loop_mask_3 uses) move every vertex by a mask over
/// its one-ring, and sphere rounds put the edge midpoints back on a sphere (icosphere refinement).
/// Crease edges, when given, take Hoppe et al.'s (1994) crease rules, the ones
/// geom/loop_patch_basis evaluates: a crease is refined like a boundary (midpoints, cubic
/// B-spline masks along it), a vertex on three or more sharp edges (crease or boundary) is a
/// corner and stays, a vertex on one crease (a dart) is smooth. Both halves of a crease edge are
/// creases again, so a CAD part's sharp edges stay sharp however often it is refined.
/// Each mask adds its terms in increasing id order, so a vertex's bits depend only on its
/// neighbours' bits. A vertex's position after R rounds depends on the coarse triangles that share
/// a vertex with the coarse cell it lies on: a patch gives exact positions on the coarse triangles
/// whose one-ring it holds, and arbitrary ones near its own border (the mesh's true boundaries and
/// the patch's border both follow the boundary rule).
#include "geom/mesh_topology.hpp"
#include "geom/triangle_mesh.hpp"

#include <array>
#include <cstdint>
#include <span>
#include <vector>

namespace texsim::geom {

/// One round of refinement: every triangle split into four at its edge midpoints, and where the
/// vertices go.
/// Three flags of a triangle, one per edge; entry i belongs to the edge opposite corner i.
using EdgeFlags = std::array<char, 3>;

/// Per triangle of `topology`'s mesh, the flags of its edges in `edge_flags` (per edge).
std::vector<EdgeFlags> triangle_edge_flags(const MeshTopology& topology,
                                           std::span<const char> edge_flags);
/// Per edge of `topology`, set where a triangle flags it in `triangle_flags` (per triangle).
std::vector<char> edge_flags(const MeshTopology& topology,
                             std::span<const EdgeFlags> triangle_flags);

struct RefinementStep {
  enum class Rule : std::int32_t {
    kLoop,  ///< Loop's masks: towards Loop's limit surface (C2 except at extraordinary vertices;
            ///< boundaries: cubic B-splines)
    kSphere ///< midpoints projected onto the sphere (centre, radius); old vertices stay
  };
  Rule rule = Rule::kLoop;
  std::array<double, 3> centre{0, 0, 0}; ///< plain doubles: steps travel between ranks as bytes
  double radius = 1.0;
};

/// Coarse triangles to refine, in local numbering, with their ids on the whole coarse mesh.
struct CoarsePatch {
  TriangleMesh mesh;
  std::vector<std::int64_t> vertex_id;   ///< coarse vertex id of each local vertex
  std::vector<std::int64_t> triangle_id; ///< coarse triangle id of each local triangle
  /// Coarse edge ids of each local triangle; entry i is the edge opposite corner i.
  std::vector<std::array<std::int64_t, 3>> triangle_edge_id;
  /// Per local triangle, 1 where the edge opposite corner i is a crease; empty: no creases.
  std::vector<EdgeFlags> triangle_edge_crease;
  std::int64_t coarse_vertices = 0; ///< V and E of the whole coarse mesh (the id layout)
  std::int64_t coarse_edges = 0;

  /// The whole of `mesh` as one patch (edge ids from its MeshTopology), with `creases` (per edge
  /// of that topology, geom::crease_edges; empty for none).
  static CoarsePatch whole(const TriangleMesh& mesh, std::span<const char> creases = {});
};

/// Cuts patches out of one coarse mesh: chosen triangles and the rings of triangles sharing a
/// vertex with them. Reuses its scratch, so cutting every rank's patch costs O(patches), not
/// O(ranks x mesh). Serial.
class PatchCutter {
public:
  /// `mesh`, `topology` and `creases` (per edge of `topology`, empty for none) must outlive the
  /// cutter.
  PatchCutter(const TriangleMesh& mesh, const MeshTopology& topology,
              std::span<const char> creases = {});

  /// `seeds` (triangle ids) and `rings` rings around them, as a patch numbered by increasing
  /// triangle and vertex id. `ring_of`, when not null, gets each patch triangle's ring (0: a seed).
  CoarsePatch cut(std::span<const std::int32_t> seeds, int rings,
                  std::vector<std::int32_t>* ring_of = nullptr);

private:
  const TriangleMesh& mesh_;
  const MeshTopology& topology_;
  std::span<const char> creases_;
  int cut_count_ = 0;
  // The last cut that met each triangle and vertex, and local vertex numbers.
  std::vector<int> triangle_stamp_;
  std::vector<int> vertex_stamp_;
  std::vector<std::int32_t> local_of_;
};

struct RefinedPatch {
  TriangleMesh mesh;
  std::vector<std::int64_t> vertex_id; ///< hierarchical id of each vertex (see above)
  std::vector<std::int32_t> parent;    ///< local coarse triangle each fine triangle lies in
  /// Crease flags of each fine triangle's edges (the halves of the coarse creases); empty when
  /// the patch has none.
  std::vector<EdgeFlags> triangle_edge_crease;
};

/// Number of vertices of the whole mesh after `rounds` rounds: V + E (n - 1) + T (n-1)(n-2)/2.
std::int64_t refined_vertex_count(std::int64_t vertices, std::int64_t edges, std::int64_t triangles,
                                  int rounds);

/// Applies `steps` in order to `patch`. Fine triangles keep their coarse triangle's orientation.
/// Throws texsim::Error on an edge shared by more than two triangles. Serial.
RefinedPatch refine_patch(const CoarsePatch& patch, std::span<const RefinementStep> steps);

/// The whole mesh refined by `steps`, vertex i being the fine vertex of hierarchical id i, with
/// `creases` (per edge of MeshTopology(mesh), empty for none) kept sharp; `fine_creases`, when
/// not null, gets the fine mesh's (per edge of its MeshTopology). Serial.
TriangleMesh refine(const TriangleMesh& mesh, std::span<const RefinementStep> steps,
                    std::span<const char> creases = {}, std::vector<char>* fine_creases = nullptr);

} // namespace texsim::geom
