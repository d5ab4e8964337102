#pragma once
/// Turk's simulation mesh over a polyhedral surface (1991, Part Two), distributed: n points spread
/// evenly by relaxation, each the centre of a cell that is its Voronoi region on the surface (the
/// exact restricted Voronoi diagram on the input triangles). A cell knows its area, its neighbours
/// and, per neighbour, the coupling (shared border length / distance between the centres) that
/// weighs diffusion between them.
///
/// Distribution: after relaxation the cells are numbered along a Morton curve of their positions
/// (neighbours get near ids, so stencil loops stay in cache) and each rank owns an equal
/// contiguous run of ids, which is also the PETSc block numbering of par::GhostedVector;
/// the input triangles are Morton-partitioned separately, and each rank computes the Voronoi pieces
/// of its triangles from its own cells plus a halo, then sends areas and border lengths to the
/// cells' owners. Cell ids depend only on the seed and the mesh: every per-cell sum runs in id
/// order, so every number here is the same on any number of ranks.
#include "geom/distributed_triangles.hpp"
#include "geom/point_relaxation.hpp"
#include "geom/restricted_voronoi.hpp"
#include "geom/surface_point.hpp"
#include "geom/triangle_mesh.hpp"
#include "par/comm.hpp"

#include <cstdint>
#include <span>
#include <vector>

namespace texsim::geom {

struct SurfaceCellsSettings {
  std::int64_t count = 10000;    ///< number of cells n
  RelaxationSettings relaxation; ///< Turk's repulsion sweeps
  double halo_spacings = 6.0;    ///< halo width around a rank's triangles, in cell spacings
  /// Keep each rank's Voronoi pieces with their polygons (pieces(): turk_rd draws the cells);
  /// without, they are dropped once the areas and borders are summed.
  bool keep_pieces = true;
};

/// How the cells are split across ranks.
struct CellPartitionQuality {
  std::int64_t edge_cut = 0;   ///< neighbour pairs with the two cells on different ranks
  double imbalance = 1.0;      ///< largest owned count over the mean
  std::int64_t ghosts_max = 0; ///< most stencil ghosts on one rank
};

class SurfaceCells {
public:
  /// Places, relaxes and tiles on the split surface (each rank tiles its share of the
  /// triangles). Collective.
  SurfaceCells(const par::Comm& comm, const DistributedTriangles& surface, std::uint64_t seed,
               const SurfaceCellsSettings& settings);

  std::int64_t global_count() const { return global_count_; }
  std::int64_t owned_begin() const { return owned_begin_; }
  /// First global block index of every rank's cells, and the total at the end (size + 1 entries).
  std::span<const std::int64_t> rank_offsets() const { return rank_offsets_; }
  std::int32_t owned_count() const { return std::int32_t(points_.size()); }

  /// Owned cells, increasing ids: id, centre on the surface, area.
  std::span<const std::int64_t> ids() const { return ids_; }
  std::span<const SurfacePoint> points() const { return points_; }
  std::span<const double> areas() const { return areas_; }

  /// Stencil: row i (owned cell) lists local indices (owned first, then stencil ghosts) of its
  /// neighbours in increasing id order; couplings() is parallel to the CSR indices.
  const CsrAdjacency& neighbors() const { return neighbors_; }
  std::span<const double> couplings() const { return couplings_; }
  /// Global block index (owned_begin numbering) of each stencil ghost, in local order.
  std::span<const std::int32_t> ghost_blocks() const { return ghost_blocks_; }
  std::span<const std::int64_t> ghost_ids() const { return ghost_ids_; }
  std::span<const Vec3> ghost_positions() const { return ghost_positions_; }

  /// This rank's input triangles (ids in the whole mesh, increasing) and their Voronoi pieces; a
  /// piece's `seed` indexes the view, its `triangle` is an id in the whole mesh. No pieces
  /// without SurfaceCellsSettings::keep_pieces.
  std::span<const std::int32_t> triangles() const { return triangles_; }
  const std::vector<VoronoiPiece>& pieces() const { return pieces_; }
  /// The view: every owned cell (in owned order) followed by the other ranks' cells near this
  /// rank's triangles (increasing id), with their global block indices: the local layout of a
  /// GhostedVector whose ghosts are view_blocks() past owned_count().
  std::span<const std::int32_t> view_blocks() const { return view_blocks_; }
  std::span<const std::int64_t> view_ids() const { return view_ids_; }
  std::span<const Vec3> view_positions() const { return view_positions_; }

  double surface_area() const { return surface_area_; }
  /// sqrt(surface area / n): the typical distance between neighbouring cells.
  double spacing() const { return spacing_; }
  const CellPartitionQuality& quality() const { return quality_; }
  const RelaxationReport& relaxation() const { return relaxation_; }

private:
  void number_along_morton_curve(const par::Comm& comm, const Box3& bounds,
                                 DistributedSurfacePoints relaxed);
  void build_view(const par::Comm& comm, const DistributedTriangles& surface, double halo,
                  bool keep_polygons);
  void reduce_pieces(const par::Comm& comm, bool keep_pieces);
  void build_stencil(const par::Comm& comm);

  std::int64_t global_count_ = 0;
  std::int64_t owned_begin_ = 0;
  std::vector<std::int64_t> rank_offsets_;
  std::vector<std::int64_t> ids_;
  std::vector<SurfacePoint> points_;
  std::vector<double> areas_;
  CsrAdjacency neighbors_;
  std::vector<double> couplings_;
  std::vector<std::int32_t> ghost_blocks_;
  std::vector<std::int64_t> ghost_ids_;
  std::vector<Vec3> ghost_positions_;
  std::vector<std::int32_t> triangles_;
  std::vector<VoronoiPiece> pieces_;
  std::vector<std::int32_t> view_blocks_;
  std::vector<std::int64_t> view_ids_;
  std::vector<Vec3> view_positions_;
  std::vector<int> view_owners_;
  /// Per owned cell: (neighbour id, border length) before symmetrisation, filled by reduce_pieces.
  std::vector<std::vector<std::pair<std::int64_t, double>>> borders_;
  double surface_area_ = 0;
  double spacing_ = 0;
  CellPartitionQuality quality_;
  RelaxationReport relaxation_;
};

} // namespace texsim::geom
