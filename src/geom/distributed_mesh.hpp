#pragma once
/// A triangle mesh shared by all ranks, with its vertices partitioned for PETSc: vertices are
/// renumbered so that rank r owns the contiguous range [owner_begin[r], owner_begin[r+1]) of
/// global ids (PETSc's ownership), and each rank knows the non-owned neighbours of its vertices
/// (ghosts) and the triangles touching its vertices (what it needs to assemble its rows).
///
/// The whole mesh is kept on every rank (geometry is small next to the solver state and makes
/// output, curvature and repartitioning simple); the distributed part is the unknowns.
#include "geom/mesh_topology.hpp"
#include "geom/triangle_mesh.hpp"
#include "par/comm.hpp"

#include <cstdint>
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
};

class DistributedMesh {
public:
  /// Partitions `mesh` (identical on every rank) over `comm`. Collective.
  DistributedMesh(const par::Comm& comm, const TriangleMesh& mesh, PartitionMethod method);

  /// The whole mesh in global (PETSc) vertex order.
  const TriangleMesh& mesh() const { return mesh_; }
  const MeshTopology& topology() const { return topology_; }
  /// Global vertex id -> the vertex's id in the mesh given to the constructor (for random numbers
  /// and outputs that must not depend on the partition).
  const std::vector<std::int64_t>& input_id() const { return input_id_; }

  std::int32_t owned_begin() const { return owner_begin_[rank_]; }
  std::int32_t owned_end() const { return owner_begin_[rank_ + 1]; }
  std::int32_t owned_count() const { return owned_end() - owned_begin(); }
  std::int32_t global_count() const { return mesh_.num_vertices(); }
  /// Owning rank of a global vertex id.
  int owner(std::int32_t vertex) const;

  /// Non-owned vertices adjacent to an owned one, increasing. Local numbering of a ghosted
  /// vector: owned vertices first (global - owned_begin), then ghosts in this order.
  const std::vector<std::int32_t>& ghosts() const { return ghosts_; }
  std::int32_t local_count() const { return owned_count() + std::int32_t(ghosts_.size()); }
  /// Local index (owned or ghost) of a global vertex, or -1 if this rank does not hold it.
  std::int32_t local_index(std::int32_t vertex) const;
  /// Global id of local index `local`.
  std::int32_t global_index(std::int32_t local) const;

  /// Triangles with at least one owned vertex, increasing: the elements of this rank's rows.
  const std::vector<std::int32_t>& assembly_triangles() const { return assembly_triangles_; }
  /// Triangles whose smallest global vertex is owned: every triangle belongs to exactly one rank
  /// (for outputs and sums over the surface).
  const std::vector<std::int32_t>& owned_triangles() const { return owned_triangles_; }

  /// Moves every vertex (global order, identical on every rank). Topology is unchanged.
  void set_positions(const std::vector<Vec3>& positions);

  /// The whole array in global vertex order on every rank, from each rank's owned values
  /// (`components` per vertex). Collective.
  std::vector<double> gather(const par::Comm& comm, std::span<const double> owned,
                             int components = 1) const;

  const PartitionQuality& quality() const { return quality_; }

private:
  int rank_ = 0;
  TriangleMesh mesh_;
  MeshTopology topology_;
  std::vector<std::int64_t> input_id_;
  std::vector<std::int32_t> owner_begin_;
  std::vector<std::int32_t> ghosts_;
  std::vector<std::int32_t> assembly_triangles_;
  std::vector<std::int32_t> owned_triangles_;
  PartitionQuality quality_;
};

} // namespace texsim::geom
