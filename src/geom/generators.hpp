#pragma once
/// Synthetic test surfaces: sphere, torus, box, a flat square, and a noisy copy of any mesh. All
/// manifold and outward-oriented (the square faces +z); all but the square are closed. Serial and
/// deterministic.
#include "geom/triangle_mesh.hpp"

#include <cstdint>

namespace texsim::geom {

/// Icosahedron refined `level` times by splitting every triangle into four at its edge midpoints,
/// every vertex projected onto the sphere of `radius` centred at the origin. Level l has
/// 10 * 4^l + 2 vertices and 20 * 4^l triangles (level 0: 12, level 7: 163,842 vertices).
/// 0 <= level <= 10.
TriangleMesh icosphere(int level, double radius = 1.0);

/// Torus around the z axis: tube centre at distance `major` from the axis, tube radius `minor`,
/// `n_major` x `n_minor` vertices on a regular angular grid, each grid quad split into two
/// triangles. Needs major > minor > 0, n_major >= 3, n_minor >= 3.
TriangleMesh torus(double major, double minor, int n_major, int n_minor);

/// Surface of the axis-aligned box [-size/2, size/2], each face a regular grid of
/// cells_per_edge x cells_per_edge cells (two triangles each) sharing vertices along the box edges:
/// 6 n^2 + 2 vertices, 12 n^2 triangles. Needs size > 0 componentwise and
/// 1 <= cells_per_edge <= 4096.
TriangleMesh box(const Vec3& size, int cells_per_edge);

/// The square [0, size.x] x [0, size.y] in the plane z = 0, a regular grid of cells_per_edge x
/// cells_per_edge cells, each split into two triangles along the same diagonal, facing +z:
/// (n + 1)^2 vertices in row-major order (x fastest), 2 n^2 triangles. An open surface with one
/// boundary loop: the flat fluid sheet of analytic flows. Needs size.x, size.y > 0 and
/// 1 <= cells_per_edge <= 4096.
TriangleMesh plane(const Vec3& size, int cells_per_edge);

/// CounterRng stream used by noisy().
inline constexpr std::uint32_t kNoisyMeshStream = 0x4e01;

/// A copy of `mesh` with vertex v moved along its area-weighted unit normal by
/// amplitude * U(-1, 1), the uniform draw taken from CounterRng(seed, kNoisyMeshStream) keyed by
/// vertex id v (step 0): the same seed gives the same positions, and no vertex moves further than
/// |amplitude|. Model units.
TriangleMesh noisy(const TriangleMesh& mesh, double amplitude, std::uint64_t seed);

} // namespace texsim::geom
