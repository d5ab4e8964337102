#pragma once
/// What a rank reads of a level around its own run of vertices: the triangles with a corner in
/// the run (its star, RetiledLevel::star). The run's normals, 1-rings and frame pieces come from
/// it, so no rank needs the whole level for them.
#include "geom/distributed_triangles.hpp"
#include "geom/mesh_topology.hpp"
#include "geom/triangle_mesh.hpp"
#include "par/comm.hpp"
#include "pipelines/surface_synthesis/mesh_pyramid.hpp"

#include <cstdint>
#include <span>

namespace texsim::pipelines::surface_synthesis {

/// The triangles of `level` with a corner in this rank's run, by increasing id, with local
/// vertices by increasing id (geom::LocalSurface): every rank sends each of its share of the
/// level's triangles (corner ids) to the owners of its corners, and the corners' positions come
/// from their owners' runs. Needs the level's triangles, runs and positions (distribute_level
/// makes RetiledLevel::star with it). Algorithms that depend only on the order and corners of a
/// vertex's triangles (vertex normals, 1-rings) give the whole level's bits on it for the run's
/// vertices. Collective.
geom::LocalSurface run_star(const par::Comm& comm, const RetiledLevel& level);

/// The local index of level vertex `first` in `star`, checking that the run [first, first +
/// count) is there as consecutive local vertices (every vertex of a level is in a triangle).
std::int32_t star_run_begin(const geom::LocalSurface& star, std::int64_t first, std::int64_t count);

/// The 1-rings (vertices sharing a triangle, by increasing id) of vertices [first, first +
/// count) of `mesh`, row i for vertex first + i, found by one pass over the triangles. Serial.
geom::CsrAdjacency run_rings(const geom::TriangleMesh& mesh, std::int64_t first,
                             std::int64_t count);

/// The same for the run [first, first + count) held by `star` (run_star), with the level's
/// vertex ids: the rows the whole level gives.
geom::CsrAdjacency run_rings(const geom::LocalSurface& star, std::int64_t first,
                             std::int64_t count);

/// The 1-rings of rank `rank`'s run of `level` (its own), from the level's star: what
/// relax_directions reads.
geom::CsrAdjacency run_rings(const RetiledLevel& level, int rank);

} // namespace texsim::pipelines::surface_synthesis
