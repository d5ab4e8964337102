#pragma once
/// The triangles a rank's points can reach in their next move along a split surface
/// (DistributedTriangles), and a SurfaceWalker over them: what Turk's relaxation needs of the
/// surface, with no rank holding all of it.
///
/// A move of length at most L stays within distance L of its start (the path along the surface
/// is at least as long as the straight line), so the triangles it crosses all come within L of
/// the start. The window holds the triangles within 2 L of where the points were when it was
/// fetched, and is fetched again (by every rank together) once some point has drifted more than
/// L, so that its next move could leave it. Relaxed points rarely drift that far: on the bunny
/// (20,000 points, 40 sweeps, -n 2 and 3) the window was fetched once.
#include "geom/distributed_triangles.hpp"
#include "geom/surface_walker.hpp"
#include "par/comm.hpp"

#include <cstdint>
#include <memory>
#include <span>
#include <vector>

namespace texsim::geom {

class SurfaceWindow {
public:
  /// For points that move at most `max_move` (model units, > 0) at a time. `surface` must
  /// outlive the window.
  SurfaceWindow(const DistributedTriangles& surface, double max_move);

  /// Makes the window hold every triangle a point at one of `positions` (this rank's points)
  /// can reach in one move. Collective.
  void cover(const par::Comm& comm, std::span<const Vec3> positions);

  /// The walker over the window's triangles (local triangle numbers).
  const SurfaceWalker& walker() const { return *walker_; }
  /// The points with their triangles numbered in the window, or in the whole mesh.
  std::vector<SurfacePoint> to_local(std::span<const SurfacePoint> points) const;
  std::vector<SurfacePoint> to_global(std::vector<SurfacePoint> points) const;

  /// How many times the window was fetched, and the most triangles it held.
  int fetches() const { return fetches_; }
  std::int64_t triangles_max() const { return triangles_max_; }

private:
  const DistributedTriangles& surface_;
  double max_move_;
  double reach_;
  LocalSurface local_;
  std::unique_ptr<SurfaceWalker> walker_;
  std::vector<Vec3> anchors_; ///< the positions it was fetched around
  int fetches_ = 0;
  std::int64_t triangles_max_ = 0;
};

} // namespace texsim::geom
