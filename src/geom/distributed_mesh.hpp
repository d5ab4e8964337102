#pragma once
/// A triangle mesh split over ranks: each rank holds only its part, the vertices it owns plus
/// a halo of the triangles within kHaloRings rings of them, never the whole surface.
///
/// Rank 0 holds a coarse mesh, partitions its triangles and sends each rank its triangles and a
/// few rings around them; each rank refines its part (patch_refinement: Loop or sphere rounds) and
/// keeps the fine vertices it owns and their halo. Refining on the parts gives the same surface,
/// bit for bit, as refining the whole coarse mesh: input ids are the hierarchical ids of
/// patch_refinement (the coarse mesh's own ids without refinement), positions are the same bits.
/// Rank 0 holds the whole surface only at the coarse level (docs/fem_rd.md, "Distribution").
///
/// Vertices are renumbered so that rank r owns the contiguous range [owner_begin[r],
/// owner_begin[r+1]) of global ids (PETSc's ownership). The local mesh numbers its vertices
/// owned first (global - owned_begin), then the ghosts (non-owned neighbours of owned vertices,
/// increasing global id: the ghosts of a PETSc ghosted vector), then the rest of the halo
/// (increasing global id). Its triangles are ordered by their sorted input ids, the same order on
/// every rank, so sums over a vertex's triangles do not depend on the partition.
///
/// Three rings make per-vertex estimates that look two rings out (curvature with its vertex
/// normals and boundary fits, the mesh-density function) exact at owned vertices; the ghosts'
/// values then come from their owners (update_halo), never from an incomplete neighbourhood.
#include "geom/mesh_topology.hpp"
#include "geom/patch_refinement.hpp"
#include "geom/triangle_mesh.hpp"
#include "par/comm.hpp"
#include "par/ghosted_vector.hpp"

#include <cstdint>
#include <map>
#include <memory>
#include <span>
#include <vector>

namespace texsim::geom {

/// How the coarse triangles are split across ranks: along a Morton curve of their centroids (fast,
/// balanced counts) or by Scotch on the graph of triangles sharing an edge (smaller edge cut); both
/// are pure functions of the mesh and the rank count. A fine vertex belongs to the rank owning the
/// coarse triangle of smallest id around the coarse cell it lies on.
enum class PartitionMethod { kMorton, kScotch };

struct PartitionQuality {
  std::int64_t edge_cut = 0;   ///< edges whose vertices are owned by different ranks
  double imbalance = 1.0;      ///< most vertices on one rank over the mean
  std::int64_t ghosts_max = 0; ///< most ghost vertices on one rank
  std::int64_t halo_max = 0;   ///< most non-owned vertices (ghosts and outer halo) on one rank
};

class DistributedMesh {
public:
  static constexpr int kHaloRings = 3;

  /// Partitions `root_mesh`, read on rank 0 (ignored on the other ranks), over `comm` and gives
  /// each rank its part, refined by `refinement` (the same steps on every rank) with the crease
  /// edges `root_creases` (rank 0: per edge of MeshTopology(root_mesh), empty for none) kept
  /// sharp. Collective.
  DistributedMesh(const par::Comm& comm, const TriangleMesh& root_mesh, PartitionMethod method,
                  std::span<const RefinementStep> refinement = {},
                  std::span<const char> root_creases = {});

  const par::Comm& comm() const { return comm_; }

  /// This rank's part: owned vertices, ghosts, outer halo (see above).
  const TriangleMesh& mesh() const { return mesh_; }
  const MeshTopology& topology() const { return topology_; }
  /// Per edge of topology(), 1 for a crease (the halves of the root mesh's creases); empty when
  /// the root mesh had none.
  std::span<const char> creases() const { return creases_; }
  /// Local vertex -> its id in the refined mesh (patch_refinement's hierarchical ids; without
  /// refinement, its id in the mesh given to the constructor): for random numbers, outputs and
  /// checkpoints that must not depend on the partition.
  const std::vector<std::int64_t>& input_id() const { return input_id_; }
  std::span<const std::int64_t> owned_input_ids() const {
    return std::span(input_id_).first(std::size_t(owned_count()));
  }

  std::int32_t owned_begin() const { return owner_begin_[rank_]; }
  std::int32_t owned_end() const { return owner_begin_[rank_ + 1]; }
  std::int32_t owned_count() const { return owned_end() - owned_begin(); }
  std::int32_t global_count() const { return owner_begin_.back(); }
  std::int64_t global_triangle_count() const { return global_triangles_; }

  /// Global ids of the ghosts, increasing.
  std::span<const std::int32_t> ghosts() const;
  /// Owned vertices and ghosts: the local part of a ghosted vector (the outer halo follows them
  /// in the mesh).
  std::int32_t local_count() const { return owned_count() + ghost_count_; }
  /// Local index of a global vertex, or -1 if this rank does not hold it.
  std::int32_t local_index(std::int32_t vertex) const;
  /// Global id of local vertex `local`.
  std::int32_t global_index(std::int32_t local) const { return global_id_[local]; }

  /// Local triangles with at least one owned vertex, increasing: the elements of this rank's rows.
  const std::vector<std::int32_t>& assembly_triangles() const { return assembly_triangles_; }
  /// Local triangles whose smallest global vertex is owned: every triangle of the surface belongs
  /// to exactly one rank (for outputs and sums over the surface).
  const std::vector<std::int32_t>& owned_triangles() const { return owned_triangles_; }

  /// Replaces every local position (owned and halo). Not collective.
  void set_positions(const std::vector<Vec3>& positions);
  /// Sets the owned positions (xyz per owned vertex) and fetches the halo's from their owners.
  /// Collective.
  void set_owned_positions(std::span<const double> owned_xyz);

  /// Fills the halo entries of `values` (`components` per local mesh vertex) from the owners'
  /// entries. Collective.
  void update_halo(std::span<double> values, int components = 1) const;

  const PartitionQuality& quality() const { return quality_; }
  /// Seconds rank 0 spent partitioning the coarse mesh and cutting every rank's part: the serial
  /// share of the construction (the rest, each rank refining and setting up its own part, runs in
  /// parallel).
  double root_seconds() const { return root_seconds_; }

private:
  par::GhostedVector& halo_vector(int components) const;

  par::Comm comm_;
  int rank_ = 0;
  TriangleMesh mesh_;
  MeshTopology topology_;
  std::vector<char> creases_;
  std::vector<std::int32_t> global_id_;
  std::vector<std::int64_t> input_id_;
  std::vector<std::int32_t> owner_begin_;
  std::int32_t ghost_count_ = 0;
  std::int64_t global_triangles_ = 0;
  std::vector<std::int32_t> assembly_triangles_;
  std::vector<std::int32_t> owned_triangles_;
  PartitionQuality quality_;
  double root_seconds_ = 0;
  /// One PETSc ghosted vector per block size in use: the halo exchange plan is built once.
  mutable std::map<int, std::unique_ptr<par::GhostedVector>> halo_vectors_;
};

} // namespace texsim::geom
