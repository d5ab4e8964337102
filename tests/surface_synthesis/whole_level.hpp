#pragma once
// The whole of a retiled level on every rank, for tests that compare a rank's work with a serial
// reference on the whole level.
#include "geom/triangle_mesh.hpp"
#include "par/allgather_runs.hpp"
#include "par/comm.hpp"
#include "par/record_exchange.hpp"
#include "pipelines/surface_synthesis/mesh_pyramid.hpp"

#include <mpi.h>

#include <algorithm>
#include <vector>

namespace texsim::pipelines::surface_synthesis {

/// Every rank's run of per-vertex vectors (positions, normals, directions) on every rank.
inline std::vector<geom::Vec3> whole_runs(const par::Comm& comm, const RetiledLevel& level,
                                          std::span<const geom::Vec3> run) {
  std::vector<geom::Vec3> all(std::size_t(level.vertex_count()));
  std::copy(run.begin(), run.end(), all.begin() + level.run_begin(comm.rank));
  par::allgather_runs(comm, level.rank_offsets, all.data(), 3, MPI_DOUBLE);
  return all;
}

/// The level's whole mesh on every rank. Collective.
inline geom::TriangleMesh whole_level_mesh(const par::Comm& comm, const RetiledLevel& level) {
  geom::TriangleMesh mesh;
  mesh.triangles = gather_level_mesh(comm, level).triangles;
  par::broadcast_records(comm, mesh.triangles);
  mesh.positions = whole_runs(comm, level, level.positions);
  return mesh;
}

} // namespace texsim::pipelines::surface_synthesis
