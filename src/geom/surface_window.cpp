#include "geom/surface_window.hpp"

#include "core/error.hpp"
#include "geom/mesh_topology.hpp"

#include <mpi.h>

#include <algorithm>

namespace texsim::geom {

SurfaceWindow::SurfaceWindow(const DistributedTriangles& surface, double max_move)
    : surface_(surface), max_move_(max_move), reach_(2.0 * max_move) {
  TEXSIM_VERIFY(max_move > 0.0, "SurfaceWindow: max_move " << max_move << " must be positive");
}

void SurfaceWindow::cover(const par::Comm& comm, std::span<const Vec3> positions) {
  // A relative margin on the move covers its rounding (the capped move's length, the projection
  // into a triangle's plane).
  int stale = fetches_ == 0 || positions.size() != anchors_.size();
  for (std::size_t i = 0; !stale && i < positions.size(); ++i)
    stale = (positions[i] - anchors_[i]).norm() + max_move_ * (1.0 + 1e-6) > reach_;
  MPI_Allreduce(MPI_IN_PLACE, &stale, 1, MPI_INT, MPI_LOR, comm.raw);
  if (!stale)
    return;
  local_ = surface_.window(comm, positions, reach_);
  walker_ = std::make_unique<SurfaceWalker>(local_.mesh, MeshTopology(local_.mesh));
  anchors_.assign(positions.begin(), positions.end());
  ++fetches_;
  triangles_max_ = std::max(triangles_max_, std::int64_t(local_.triangle_ids.size()));
}

std::vector<SurfacePoint> SurfaceWindow::to_local(std::span<const SurfacePoint> points) const {
  std::vector<SurfacePoint> local(points.begin(), points.end());
  for (auto& p : local) {
    const std::int32_t t = local_.local_triangle(p.triangle);
    TEXSIM_VERIFY(t >= 0, "SurfaceWindow: triangle " << p.triangle << " of a point is not held");
    p.triangle = t;
  }
  return local;
}

std::vector<SurfacePoint> SurfaceWindow::to_global(std::vector<SurfacePoint> points) const {
  for (auto& p : points)
    p.triangle = std::int32_t(local_.triangle_ids[std::size_t(p.triangle)]);
  return points;
}

} // namespace texsim::geom
