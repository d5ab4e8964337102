#pragma once
/// Areas, normals and edge lengths of a triangle mesh. Serial; model units throughout.
#include "geom/triangle_mesh.hpp"

#include <array>
#include <vector>

namespace texsim::geom {

/// Area of triangle (a, b, c), in model units squared.
double triangle_area(const Vec3& a, const Vec3& b, const Vec3& c);

/// Barycentric weights of p in triangle (a, b, c): of the orthogonal projection of p into the
/// triangle's plane, so a*w[0] + b*w[1] + c*w[2] is that projection; they sum to 1 and are not
/// clamped (negative outside the triangle). {1, 0, 0} for a triangle of zero area.
std::array<double, 3> barycentric_weights(const Vec3& a, const Vec3& b, const Vec3& c,
                                          const Vec3& p);

/// Area of each triangle, indexed like mesh.triangles.
std::vector<double> triangle_areas(const TriangleMesh& mesh);

/// Sum of the triangle areas.
double total_area(const TriangleMesh& mesh);

/// Unit normal of each triangle by the right-hand rule over its corners; zero for a triangle of
/// zero area.
std::vector<Vec3> triangle_normals(const TriangleMesh& mesh);

/// Unit vertex normals: the area-weighted sum of the incident triangles' normals, normalised; zero
/// for a vertex without triangles (or whose triangles cancel).
std::vector<Vec3> vertex_normals(const TriangleMesh& mesh);

/// The same for the vertices [first, first + count) only (vertex first + i at i), from one pass
/// over the triangles: the same bits as those entries of the whole call, for a rank's run.
std::vector<Vec3> vertex_normals(const TriangleMesh& mesh, std::int64_t first, std::int64_t count);

/// Mean length of the triangle sides (an edge shared by two triangles counts twice); 0 for a mesh
/// without triangles.
double mean_edge_length(const TriangleMesh& mesh);

} // namespace texsim::geom
