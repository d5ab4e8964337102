#pragma once
/// Evenly spaced points on a surface by Turk's relaxation ("Generating textures on arbitrary
/// surfaces using reaction-diffusion", SIGGRAPH '91, part two): random area-weighted points repel
/// their neighbours within a radius r and move along the surface, sweep after sweep, until they are
/// nearly hexagonally spaced. Serial kernels plus the distributed driver.
#include "geom/distributed_triangles.hpp"
#include "geom/point_halo.hpp"
#include "geom/surface_point.hpp"
#include "geom/surface_walker.hpp"
#include "geom/triangle_mesh.hpp"
#include "par/comm.hpp"

#include <cstdint>
#include <span>
#include <vector>

namespace texsim::geom {

/// Defaults measured on a unit icosphere (2000 to 20000 points) and the Stanford bunny (20000 and
/// 100000 points): the coefficient of variation of nearest-neighbour distances falls from 0.52
/// (random) to 0.08 after 10 sweeps and 0.048 after 40. A step of 2 converges slightly faster,
/// 3 and more oscillate.
struct RelaxationSettings {
  int iterations = 40;        ///< Turk's relaxation sweeps
  double radius_factor = 2.0; ///< repulsion radius r = radius_factor * sqrt(surface area / n)
  /// Fraction of r a point may move per sweep: the move is step * F / n_r with F the summed
  /// force (model units) and n_r = pi radius_factor^2 the mean number of points within r, capped
  /// at step * r.
  double step = 1.5;
};

struct RelaxationReport {
  double radius = 0.0;                       ///< repulsion radius r, model units
  std::vector<double> seconds_per_iteration; ///< wall time of each sweep, max over ranks
  double seconds_setup = 0.0;                ///< placement and partition, max over ranks
  std::int64_t max_halo_points = 0;          ///< largest halo any rank received in a sweep
  /// Times the ranks fetched the triangles their points can reach (SurfaceWindow), and the most
  /// triangles one rank held for that: its share of the surface, never the whole of it.
  int window_fetches = 0;
  std::int64_t window_triangles_max = 0;
  /// Mean move per point of each sweep as a fraction of r (all ranks): falls as points settle.
  std::vector<double> mean_move_per_iteration;
};

/// r = radius_factor * sqrt(area / count), model units.
double repulsion_radius(double area, std::int64_t count, double radius_factor);

/// Turk's repulsion of P by Q at distance d = |P - Q| < radius: (radius - d) (P - Q) / d, falling
/// to zero at the radius. Coincident points (d <= 1e-9 radius) push each other apart along a
/// direction drawn from the two ids, opposite for the two. Zero at d >= radius.
Vec3 repulsion(const Vec3& p, std::int64_t p_id, const Vec3& q, std::int64_t q_id, double radius);

/// The move of one sweep for the summed force `force` (model units): step * force / n_r,
/// n_r = pi (radius / spacing)^2 with spacing = radius / radius_factor, capped at step * radius.
Vec3 relaxation_move(const Vec3& force, double radius, const RelaxationSettings& settings);

/// One Jacobi sweep on the points of one rank (serial kernel, OpenMP over `points`): every point
/// sums repulsion() from all points of `points` and `halo` within `radius` of it, in increasing
/// id order (so the result does not depend on how points are split among ranks or threads), and
/// moves by relaxation_move() along the surface with `walker`. `ids` must increase, `halo` be
/// sorted by id (as exchange_point_halo() returns it), and no id appear twice. Returns the new
/// positions, indexed like `points`; `move_sum` (optional) receives the sum of the move lengths
/// (model units).
std::vector<SurfacePoint>
relaxation_sweep(const SurfaceWalker& walker, std::span<const std::int64_t> ids,
                 std::span<const SurfacePoint> points, std::span<const HaloPoint> halo,
                 double radius, const RelaxationSettings& settings, double* move_sum = nullptr);

/// Collective over comm. Places `count` random points (random_surface_points on the whole mesh
/// with ids 0..count-1 and `seed`, the same bits; each rank asks for an even share of the ids,
/// DistributedTriangles::random_points), gives each rank an even run of them along a Morton curve
/// of the initial positions in the mesh's bounding box (par::distributed_sort; ownership then
/// stays fixed), and runs settings.iterations sweeps of Turk's relaxation with
/// r = repulsion_radius(total area, count, radius_factor): each sweep refreshes the halo
/// (exchange_point_halo with the covering_boxes() of the owned points, cells of 3 r, grown by r)
/// and calls relaxation_sweep() with a SurfaceWindow's walker (the triangles the owned points can
/// reach, fetched from the ranks holding them). The gathered result is the same, bit for bit, on
/// any number of ranks and threads, and the same as on the whole mesh. Prints a progress line on
/// rank 0 when the sweeps take long. `report` (optional, not owned) receives radius and timings,
/// the same on every rank.
DistributedSurfacePoints relaxed_surface_points(const par::Comm& comm,
                                                const DistributedTriangles& surface,
                                                std::int64_t count, std::uint64_t seed,
                                                const RelaxationSettings& settings,
                                                RelaxationReport* report = nullptr);

/// Euclidean nearest-neighbour distances of a point set: their mean and coefficient of variation
/// (std / mean), the evenness measure of a relaxation (about 0.52 for random points, near 0 for
/// a hexagonal lattice). Serial; needs at least two points.
struct NeighborSpacing {
  double mean = 0.0;
  double cv = 0.0;
  double min = 0.0;
  double max = 0.0;
};
NeighborSpacing nearest_neighbor_spacing(std::span<const Vec3> positions);

} // namespace texsim::geom
