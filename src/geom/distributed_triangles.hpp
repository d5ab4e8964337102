#pragma once
/// A surface whose triangles are split over the ranks, for work that walks over the surface near
/// scattered points (Turk's retiling): each rank holds its share of the triangles (even runs along
/// a Morton curve of their centroids, morton_triangle_parts) and fetches, when it needs them, the
/// other ranks' triangles near its points. No rank holds the whole surface once it is split.
///
/// Local copies (LocalSurface) number their triangles and vertices in increasing order of their
/// ids in the whole mesh. Serial algorithms whose results depend only on that order and on a
/// triangle's neighbourhood (the surface walker, the restricted Voronoi diagram, Loop refinement
/// of a patch) then give the same bits on a local copy as on the whole mesh wherever the copy
/// holds the whole neighbourhood.
#include "geom/patch_refinement.hpp"
#include "geom/point_halo.hpp"
#include "geom/surface_point.hpp"
#include "geom/triangle_mesh.hpp"
#include "par/comm.hpp"

#include <array>
#include <cstdint>
#include <functional>
#include <span>
#include <vector>

namespace texsim::geom {

/// The xyz of triangle t's three corners, as TriangleRecord::corners holds them.
std::array<double, 9> corners_of(const TriangleMesh& mesh, std::size_t t);

/// One triangle as it travels between ranks.
struct TriangleRecord {
  std::int64_t id = -1;                 ///< index in the whole mesh's triangles
  std::array<std::int64_t, 3> vertex{}; ///< indices in the whole mesh's positions
  std::array<double, 9> corners{};      ///< xyz of the three corners
  std::array<char, 3> creases{};        ///< EdgeFlags of the triangle's edges
  std::array<char, 5> padding{};        ///< no indeterminate bytes on the wire
};

/// Some of the whole mesh's triangles, numbered in the whole mesh's order.
struct LocalSurface {
  TriangleMesh mesh;                       ///< triangles and vertices by increasing id
  std::vector<std::int64_t> triangle_ids;  ///< local triangle -> id in the whole mesh
  std::vector<std::int64_t> vertex_ids;    ///< local vertex -> id in the whole mesh
  std::vector<EdgeFlags> triangle_creases; ///< crease flags per local triangle

  /// The local index of triangle `id` of the whole mesh, -1 when this copy does not hold it.
  std::int32_t local_triangle(std::int64_t id) const;
  /// Builds the copy from records with unique ids (any order).
  static LocalSurface from_records(std::vector<TriangleRecord> records);
  /// Builds the copy of triangles `ids` (increasing) of the whole mesh, with their corners'
  /// ids and crease flags; `corner_position(k, c)` gives corner c of triangle k's position
  /// (every corner of a vertex the same bits). Needs no 112-byte records.
  static LocalSurface assemble(std::vector<std::int64_t> ids,
                               std::span<const std::array<std::int64_t, 3>> corners,
                               std::vector<EdgeFlags> creases,
                               const std::function<Vec3(std::size_t, int)>& corner_position);
};

class DistributedTriangles {
public:
  /// Whether a split keeps the area prefix sums random_points() reads (80 bytes a triangle).
  enum class Sampling { area, none };

  /// Splits `root_mesh`, held by rank 0 (the others pass an empty mesh), with its crease flags
  /// (per edge of MeshTopology(root_mesh), empty for none). Rank 0 also sums the area (the
  /// serial sum of total_area) and, with Sampling::area, the area prefix sums of the random
  /// placement, so both are the bits of the whole mesh's. Collective.
  static DistributedTriangles from_root(const par::Comm& comm, const TriangleMesh& root_mesh,
                                        std::span<const char> root_creases = {},
                                        Sampling sampling = Sampling::area);
  /// The same from a mesh that every rank holds whole (each keeps its share). Collective.
  static DistributedTriangles from_replicated(const par::Comm& comm, const TriangleMesh& mesh);

  std::int64_t global_count() const { return global_count_; }
  /// total_area() of the whole mesh, the same bits.
  double total_area() const { return total_area_; }
  /// Bounding box of the whole mesh's corners (Box3::around of its positions when every vertex
  /// belongs to a triangle).
  const Box3& bounds() const { return bounds_; }
  /// The longest triangle edge of the whole mesh.
  double longest_edge() const { return longest_edge_; }

  /// This rank's share, by increasing id (held as a LocalSurface: about 40 bytes a triangle
  /// instead of a 112-byte record).
  const LocalSurface& owned_surface() const { return share_; }
  std::size_t owned_count() const { return share_.triangle_ids.size(); }
  /// Triangle k of this rank's share as it travels.
  TriangleRecord owned_record(std::size_t k) const;

  /// Every triangle (this rank's or another's) that has a point within `reach` of one of
  /// `positions`, and some farther ones. Collective.
  LocalSurface window(const par::Comm& comm, std::span<const Vec3> positions, double reach) const;
  /// Every triangle that has a point inside one of `boxes` (this rank's, e.g. covering_boxes()),
  /// and some others. Collective.
  LocalSurface window(const par::Comm& comm, std::span<const Box3> boxes) const;

  /// Points first_id .. first_id + count - 1 of random_surface_points(whole mesh, ..., seed),
  /// the same bits (SurfacePoint::triangle the id in the whole mesh), each returned by the rank
  /// holding its triangle's slot of the area prefix sums: the ids ask across the ranks, no rank
  /// holds all prefix sums. Only for a split with Sampling::area. Collective.
  DistributedSurfacePoints random_points(const par::Comm& comm, std::int64_t first_id,
                                         std::int64_t count, std::uint64_t seed) const;

private:
  /// The triangles with a sample (window()'s points standing for them) inside one of `boxes`.
  LocalSurface sampled_window(const par::Comm& comm, std::span<const Box3> boxes) const;

  /// A slot of the area prefix sums: the triangle ids [T r / p, T (r + 1) / p) on rank r.
  struct AreaSlot {
    double prefix = 0.0; ///< inclusive prefix sum of the areas in id order
    std::array<double, 9> corners{};
  };

  std::int64_t global_count_ = 0;
  double total_area_ = 0.0;
  Box3 bounds_;
  double longest_edge_ = 0.0;
  LocalSurface share_;
  bool sampling_ = false;           ///< whether the area slots are kept
  std::int64_t slots_begin_ = 0;    ///< id of this rank's first slot
  std::vector<AreaSlot> slots_;     ///< this rank's slots
  std::vector<double> slot_last_;   ///< per rank: its last prefix sum (-inf when it has none)
  std::int64_t last_positive_ = -1; ///< the last triangle of positive area
  /// window()'s sampling spacing h: the 90th percentile of the triangles' longest edges.
  double sample_spacing_ = 0.0;
};

} // namespace texsim::geom
