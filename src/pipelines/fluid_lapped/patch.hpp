#pragma once
/// A deformable lapped-texture patch (Gagnon et al. 2021, section 4): a small open triangle mesh
/// copied from the fluid surface when it is created, carried by the flow, with its lifelong rest
/// parameterisation.
#include "geom/triangle_mesh.hpp"

#include <Eigen/Core>

#include <cstdint>
#include <vector>

namespace texsim::pipelines::fluid_lapped {

struct Patch {
  /// Creation order, unique over the run: lower ids are older and lie on top in the atlas.
  std::int64_t id = -1;
  std::int32_t birth_frame = 0; ///< frame at which the patch was created
  /// Vertex positions on the current frame's surface (model units).
  std::vector<geom::Vec3> positions;
  /// Triangle of the current frame's mesh holding each vertex (after the last projection).
  std::vector<std::int32_t> surface_triangle;
  /// Rest parameterisation (LSCM at creation), one per vertex: the centre p at (0.5, 0.5), a
  /// distance r of the surface is 0.5 in uv. Never changes; the exemplar spans [0, 1]^2.
  std::vector<Eigen::Vector2d> rest_uv;
  /// Indices into positions, oriented like the fluid surface they were copied from.
  std::vector<geom::Triangle> triangles;
  /// Erosion weight w_V = Q_V B_V per vertex for the current frame (equation 3).
  std::vector<double> weights;
};

} // namespace texsim::pipelines::fluid_lapped
