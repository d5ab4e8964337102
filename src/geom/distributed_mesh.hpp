#pragma once
/// A triangle mesh split over ranks: each rank holds only its part, the vertices it owns plus
/// a halo of the triangles within kHaloRings rings of them, never the whole surface.
///
/// Vertices are renumbered so that rank r owns the contiguous range [owner_begin[r],
/// owner_begin[r+1]) of global ids (PETSc's ownership). The local mesh numbers its vertices
/// owned first (global - owned_begin), then the ghosts (non-owned neighbours of owned vertices,
/// increasing global id: the ghosts of a PETSc ghosted vector), then the rest of the halo
/// (increasing global id). Its triangles are in increasing global triangle order.
///
/// Three rings make per-vertex estimates that look two rings out (curvature with its vertex
/// normals and boundary fits, the mesh-density function) exact at owned vertices; the ghosts'
/// values then come from their owners (update_halo), never from an incomplete neighbourhood.
///
/// Rank 0 reads or generates the mesh, partitions it and sends each rank its part; that is the
/// only time one rank holds the whole surface (docs/fem_rd.md, "Distribution").
#include "geom/mesh_topology.hpp"
#include "geom/triangle_mesh.hpp"
#include "par/comm.hpp"
#include "par/ghosted_vector.hpp"

#include <cstdint>
#include <map>
#include <memory>
#include <span>
#include <vector>

namespace texsim::geom {

/// How vertices are split across ranks: along a Morton curve of their positions (fast, balanced
/// counts) or by Scotch on the vertex graph (smaller edge cut); both are pure functions of the
/// mesh and the rank count.
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
  /// each rank its part. Collective.
  DistributedMesh(const par::Comm& comm, const TriangleMesh& root_mesh, PartitionMethod method);

  const par::Comm& comm() const { return comm_; }

  /// This rank's part: owned vertices, ghosts, outer halo (see above).
  const TriangleMesh& mesh() const { return mesh_; }
  const MeshTopology& topology() const { return topology_; }
  /// Local vertex -> its id in the mesh given to the constructor (for random numbers, outputs and
  /// checkpoints that must not depend on the partition).
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
  /// Seconds rank 0 spent partitioning the whole mesh and cutting every rank's part: the serial
  /// share of the construction (the rest, each rank setting up its own part, runs in parallel).
  double root_seconds() const { return root_seconds_; }

private:
  par::GhostedVector& halo_vector(int components) const;

  par::Comm comm_;
  int rank_ = 0;
  TriangleMesh mesh_;
  MeshTopology topology_;
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
