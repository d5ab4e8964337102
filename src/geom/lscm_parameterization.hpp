#pragma once
/// Least-squares conformal parameterization of a disk-shaped triangle surface (CGAL).
#include "geom/triangle_mesh.hpp"

#include <Eigen/Core>

#include <vector>

namespace texsim::geom {

/// Flattens `disk` to the plane with the least-squares conformal map (Levy et al. 2002, through
/// CGAL's LSCM_parameterizer_3, two boundary vertices pinned): returns one uv point per vertex of
/// `disk`, in the same order, in model units up to a global similarity. A flat domain is mapped by
/// a similarity (angles kept exactly); on curved disks angles are kept in the least-squares sense.
/// uv triangles keep the orientation of the input triangles. `disk` must be a connected,
/// edge-manifold, consistently oriented mesh with exactly one boundary loop, Euler characteristic 1
/// and no isolated vertices; throws texsim::Error saying what was found otherwise, and when CGAL
/// reports a failure (the message names CGAL's status). Serial.
std::vector<Eigen::Vector2d> lscm_parameterize(const TriangleMesh& disk);

} // namespace texsim::geom
