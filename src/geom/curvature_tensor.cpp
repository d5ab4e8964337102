#include "geom/curvature_tensor.hpp"

#include <Eigen/Dense>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <span>
#include <utility>

namespace texsim::geom {

namespace {

/// A triangle's second fundamental form in its own orthonormal tangent frame (u, v).
struct FaceTensor {
  Vec3 normal = Vec3::Zero();
  Vec3 u = Vec3::Zero();
  Vec3 v = Vec3::Zero();
  Eigen::Matrix2d form = Eigen::Matrix2d::Zero();
  std::array<double, 3> corner_weight{}; ///< mixed Voronoi area of each corner; 0 if degenerate
};

/// Normal of vertex v by Max's weights: each incident corner contributes the cross product of its
/// two edges divided by both squared edge lengths.
Vec3 max_weighted_normal(const TriangleMesh& mesh, std::span<const std::int32_t> triangles,
                         std::int32_t v) {
  Vec3 sum = Vec3::Zero();
  for (const std::int32_t t : triangles) {
    const Triangle& tri = mesh.triangles[t];
    const int corner = tri[0] == v ? 0 : (tri[1] == v ? 1 : 2);
    const Vec3& p = mesh.positions[tri[corner]];
    const Vec3 a = mesh.positions[tri[(corner + 1) % 3]] - p;
    const Vec3 b = mesh.positions[tri[(corner + 2) % 3]] - p;
    const double scale = a.squaredNorm() * b.squaredNorm();
    if (scale > 0.0) {
      sum += a.cross(b) / scale;
    }
  }
  const double length = sum.norm();
  return length > 0.0 ? Vec3(sum / length) : Vec3::UnitZ();
}

/// Some unit vector orthogonal to unit `n`, chosen from the coordinate axis least aligned with it.
Vec3 any_tangent(const Vec3& n) {
  Eigen::Index axis = 0;
  n.cwiseAbs().minCoeff(&axis);
  return n.cross(Vec3::Unit(axis)).normalized();
}

/// Normal of boundary vertex v from a least-squares height field z = d x + e y + a x^2 + b xy + c
/// y^2 through v over its two-ring, in the tangent frame of the one-sided normal `rough`: a
/// one-sided normal leans towards the interior by about half an edge's turn, which would halve the
/// curvature fitted on the triangles at the boundary. Keeps `rough` when the two-ring does not
/// determine the fit or the fit turns the normal by more than 60 degrees.
Vec3 fitted_boundary_normal(const TriangleMesh& mesh, const MeshTopology& topology, std::int32_t v,
                            const Vec3& rough) {
  const CsrAdjacency& neighbors = topology.vertex_neighbors();
  std::vector<std::int32_t> ring;
  for (const std::int32_t w : neighbors.row(v)) {
    ring.push_back(w);
    for (const std::int32_t x : neighbors.row(w)) {
      ring.push_back(x);
    }
  }
  std::sort(ring.begin(), ring.end());
  ring.erase(std::unique(ring.begin(), ring.end()), ring.end());
  ring.erase(std::remove(ring.begin(), ring.end(), v), ring.end());
  if (ring.size() < 5) {
    return rough;
  }
  const Vec3& origin = mesh.positions[v];
  double scale = 0.0;
  for (const std::int32_t w : ring) {
    scale += (mesh.positions[w] - origin).squaredNorm();
  }
  scale = std::sqrt(scale / static_cast<double>(ring.size()));
  if (!(scale > 0.0)) {
    return rough;
  }
  const Vec3 u = any_tangent(rough);
  const Vec3 w = rough.cross(u);
  Eigen::MatrixXd design(static_cast<Eigen::Index>(ring.size()), 5);
  Eigen::VectorXd heights(static_cast<Eigen::Index>(ring.size()));
  for (std::size_t i = 0; i < ring.size(); ++i) {
    const Vec3 d = (mesh.positions[ring[i]] - origin) / scale;
    const double x = d.dot(u);
    const double y = d.dot(w);
    design.row(static_cast<Eigen::Index>(i)) << x, y, x * x, x * y, y * y;
    heights(static_cast<Eigen::Index>(i)) = d.dot(rough);
  }
  const Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(design);
  if (qr.rank() < 5) {
    return rough;
  }
  const Eigen::VectorXd coefficients = qr.solve(heights);
  const Vec3 fitted = (rough - coefficients(0) * u - coefficients(1) * w).normalized();
  return fitted.dot(rough) > 0.5 ? fitted : rough;
}

/// Mixed Voronoi areas of the corners of a triangle with corner dot products `dots` (of the two
/// edges leaving each corner), squared side lengths `sides` (side i opposite corner i) and `area`.
std::array<double, 3> mixed_corner_areas(const std::array<double, 3>& dots,
                                         const std::array<double, 3>& sides, double area) {
  for (int i = 0; i < 3; ++i) {
    if (dots[i] < 0.0) { // obtuse at corner i: Voronoi region leaves the triangle
      std::array<double, 3> weights{area / 4.0, area / 4.0, area / 4.0};
      weights[i] = area / 2.0;
      return weights;
    }
  }
  // cot(angle j) = dots[j] / (2 area); corner i's Voronoi area is
  // (|side to j|^2 cot(angle k) + |side to k|^2 cot(angle j)) / 8, and |side i to j| is side k.
  std::array<double, 3> weights{};
  for (int i = 0; i < 3; ++i) {
    const int j = (i + 1) % 3;
    const int k = (i + 2) % 3;
    weights[i] = (sides[k] * dots[k] + sides[j] * dots[j]) / (16.0 * area);
  }
  return weights;
}

/// Least-squares second fundamental form of triangle t given the vertex normals.
FaceTensor fit_face_tensor(const TriangleMesh& mesh, const std::vector<Vec3>& normals,
                           std::int32_t t) {
  const Triangle& tri = mesh.triangles[t];
  const std::array<Vec3, 3> p{mesh.positions[tri[0]], mesh.positions[tri[1]],
                              mesh.positions[tri[2]]};
  // edge[i] runs from corner i+1 to corner i+2 (opposite corner i).
  const std::array<Vec3, 3> edge{p[2] - p[1], p[0] - p[2], p[1] - p[0]};
  FaceTensor face;
  const Vec3 cross = edge[2].cross(-edge[1]);
  const double area = 0.5 * cross.norm();
  if (!(area > 0.0)) {
    return face;
  }
  face.normal = cross.normalized();
  face.u = edge[0].normalized();
  face.v = face.normal.cross(face.u);

  // Unknowns (E, F, G) of [E F; F G]; each edge gives two equations
  // [E F; F G] (e.u, e.v) = (dn.u, dn.v), dn the normal difference along the edge.
  Eigen::Matrix3d normal_matrix = Eigen::Matrix3d::Zero();
  Eigen::Vector3d rhs = Eigen::Vector3d::Zero();
  for (int i = 0; i < 3; ++i) {
    const Vec3 dn = normals[tri[(i + 2) % 3]] - normals[tri[(i + 1) % 3]];
    const double eu = edge[i].dot(face.u);
    const double ev = edge[i].dot(face.v);
    const Eigen::RowVector3d row_u(eu, ev, 0.0);
    const Eigen::RowVector3d row_v(0.0, eu, ev);
    normal_matrix += row_u.transpose() * row_u + row_v.transpose() * row_v;
    rhs += row_u.transpose() * dn.dot(face.u) + row_v.transpose() * dn.dot(face.v);
  }
  const Eigen::Vector3d efg = normal_matrix.ldlt().solve(rhs);
  face.form << efg(0), efg(1), efg(1), efg(2);

  std::array<double, 3> dots{};
  std::array<double, 3> sides{};
  for (int i = 0; i < 3; ++i) {
    dots[i] = (p[(i + 1) % 3] - p[i]).dot(p[(i + 2) % 3] - p[i]);
    sides[i] = edge[i].squaredNorm();
  }
  face.corner_weight = mixed_corner_areas(dots, sides, area);
  return face;
}

/// The vertex frame (u, v) with normal `from`, turned by the smallest rotation taking `from` to
/// `to` (both unit); a half turn about v when they are opposite.
std::pair<Vec3, Vec3> rotate_frame(const Vec3& u, const Vec3& v, const Vec3& from, const Vec3& to) {
  const double c = from.dot(to);
  if (c <= -1.0 + 1e-12) {
    return {-u, v};
  }
  const Vec3 k = from.cross(to);
  // Rodrigues for the rotation taking from -> to: R x = c x + k x x + k (k.x) / (1 + c).
  const auto rotate = [&](const Vec3& x) -> Vec3 {
    return c * x + k.cross(x) + k * (k.dot(x) / (1.0 + c));
  };
  return {rotate(u), rotate(v)};
}

} // namespace

std::vector<PrincipalCurvature> principal_curvatures(const TriangleMesh& mesh,
                                                     const MeshTopology& topology) {
  const std::int32_t num_vertices = mesh.num_vertices();
  const std::int32_t num_triangles = mesh.num_triangles();
  const CsrAdjacency& vertex_triangles = topology.vertex_triangles();

  std::vector<Vec3> normals(static_cast<std::size_t>(num_vertices));
#pragma omp parallel for schedule(static)
  for (std::int32_t v = 0; v < num_vertices; ++v) {
    normals[v] = max_weighted_normal(mesh, vertex_triangles.row(v), v);
  }
  const std::vector<std::int32_t>& boundary = topology.boundary_vertices();
  const auto num_boundary = static_cast<std::int64_t>(boundary.size());
  std::vector<Vec3> boundary_normals(boundary.size());
#pragma omp parallel for schedule(static)
  for (std::int64_t i = 0; i < num_boundary; ++i) {
    boundary_normals[i] = fitted_boundary_normal(mesh, topology, boundary[i], normals[boundary[i]]);
  }
  for (std::int64_t i = 0; i < num_boundary; ++i) {
    normals[boundary[i]] = boundary_normals[i];
  }

  std::vector<FaceTensor> faces(static_cast<std::size_t>(num_triangles));
#pragma omp parallel for schedule(static)
  for (std::int32_t t = 0; t < num_triangles; ++t) {
    faces[t] = fit_face_tensor(mesh, normals, t);
  }

  std::vector<PrincipalCurvature> result(static_cast<std::size_t>(num_vertices));
#pragma omp parallel for schedule(static)
  for (std::int32_t v = 0; v < num_vertices; ++v) {
    const Vec3& n = normals[v];
    const Vec3 u = any_tangent(n);
    const Vec3 w = n.cross(u);
    Eigen::Matrix2d form = Eigen::Matrix2d::Zero();
    double total_weight = 0.0;
    for (const std::int32_t t : vertex_triangles.row(v)) {
      const FaceTensor& face = faces[t];
      const Triangle& tri = mesh.triangles[t];
      const int corner = tri[0] == v ? 0 : (tri[1] == v ? 1 : 2);
      const double weight = face.corner_weight[corner];
      if (!(weight > 0.0)) {
        continue;
      }
      const auto [ru, rv] = rotate_frame(u, w, n, face.normal);
      Eigen::Matrix2d to_vertex;
      to_vertex << ru.dot(face.u), ru.dot(face.v), rv.dot(face.u), rv.dot(face.v);
      form += weight * (to_vertex * face.form * to_vertex.transpose());
      total_weight += weight;
    }
    PrincipalCurvature& out = result[v];
    out.normal = n;
    if (!(total_weight > 0.0)) {
      out.e1 = u;
      out.e2 = w;
      continue;
    }
    form /= total_weight;
    form(0, 1) = form(1, 0) = 0.5 * (form(0, 1) + form(1, 0));
    Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> eigen;
    eigen.computeDirect(form);
    out.k1 = eigen.eigenvalues()(1);
    out.k2 = eigen.eigenvalues()(0);
    const Eigen::Vector2d d1 = eigen.eigenvectors().col(1);
    out.e1 = (d1(0) * u + d1(1) * w).normalized();
    out.e2 = n.cross(out.e1);
  }
  return result;
}

} // namespace texsim::geom
