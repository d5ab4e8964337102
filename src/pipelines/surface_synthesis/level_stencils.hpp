#pragma once
/// Where the neighbourhood samples of a rank's vertices fall on the mesh (Wei-Levoy Table 3,
/// BuildMeshNeighborhood = FlattenLocalPatch + ResampleNeighborhood): for every sample the three
/// vertices of the flattened triangle holding it and their weights. Built once per level and
/// used by both passes, the neighbourhood-error metric and the halo lists (which vertices a rank
/// reads), so flattening costs one patch per vertex and level, not one per query.
#include "pipelines/surface_synthesis/mesh_pyramid.hpp"
#include "pipelines/surface_synthesis/neighbourhood_template.hpp"
#include "pipelines/surface_synthesis/orientation_field.hpp"
#include "pipelines/surface_synthesis/patch_flattening.hpp"

#include <cstdint>
#include <span>
#include <vector>

namespace texsim::pipelines::surface_synthesis {

struct LevelStencils {
  std::int64_t first = 0;        ///< first owned vertex id
  std::int64_t owned = 0;        ///< owned vertices [first, first + owned)
  std::size_t current_count = 0; ///< current-part samples per vertex
  std::size_t coarser_count = 0; ///< coarser-part samples per vertex
  /// owned * current_count samples on this level, vertex after vertex
  std::vector<SampleWeights> current;
  /// owned * coarser_count samples on the coarser level (its vertex ids)
  std::vector<SampleWeights> coarser;

  std::span<const SampleWeights> current_of(std::int64_t local) const {
    return {current.data() + std::size_t(local) * current_count, current_count};
  }
  std::span<const SampleWeights> coarser_of(std::int64_t local) const {
    return {coarser.data() + std::size_t(local) * coarser_count, coarser_count};
  }
  /// Samples that no flattened triangle covers (they read the exemplar mean).
  std::int64_t uncovered() const;
};

/// Stencils of vertices [first, first + owned) of `level`: the current part flattened from the
/// triangles around each vertex in its frame (`normals`, `directions`, t = n x s) at the level's
/// spacing d; the coarser part flattened on `coarser` from the vertex's parent face (`parents`)
/// at 2d, skipped (uncovered) where no parent face was found. `positions`, `normals`,
/// `directions` and `parents` hold one entry per owned vertex (vertex first + i at i); the
/// parent faces' corners are fetched from their owners on `coarser`. `coarser` may be null when
/// the layout has no coarser part. The patches are flattened on LevelParts of both levels around
/// the owned vertices (and their parent faces), fetched from the levels' triangles split over
/// the ranks (RetiledLevel::triangles) and dropped on return, so no rank builds the topology of a
/// whole level; the few vertices whose patches leave their parts' complete triangles are flattened
/// again on parts twice as wide around them, until none does on any rank, so every stencil is the
/// one the whole level gives. OpenMP over vertices; deterministic. Collective.
LevelStencils build_level_stencils(const par::Comm& comm, const RetiledLevel& level,
                                   std::span<const geom::Vec3> positions,
                                   std::span<const geom::Vec3> normals,
                                   std::span<const geom::Vec3> directions,
                                   const RetiledLevel* coarser, std::span<const ParentFace> parents,
                                   const NeighbourhoodTemplate& layout, std::int64_t first,
                                   std::int64_t owned);

} // namespace texsim::pipelines::surface_synthesis
