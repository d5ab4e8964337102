#pragma once
/// The C1 basis of Loop's subdivision surfaces on a triangle mesh (Bajaj, Zhang, Xu, section
/// 3.3): vertex i's function is the limit of Loop subdivision from the value 1 at i and 0 at every
/// other vertex; u = sum_i u_i phi_i, and the surface itself is sum_i x_i phi_i.
///
/// On triangle (a, b, c) the nonzero functions are those of its controls, the vertices of its
/// corners' 1-rings. A regular triangle (three interior corners of valence 6) is one quartic box
/// spline of 12 controls (geom/loop_box_spline). An irregular one is subdivided, as the paper does
/// after Stam, "until the parameter values of interest are inside a regular" sub-triangle: its
/// corners' stars are refined with Loop's masks, carrying each new vertex as a combination of the
/// controls, and the sub-triangle holding the point is followed until it is regular. Points are
/// x = a + s (b - a) + t (c - a); a point on an extraordinary corner itself is never regular
/// (quadrature points are interior).
///
/// Boundaries take Loop's boundary rules (Hoppe et al. 1994), the masks geom/patch_refinement
/// refines with: a boundary edge's new vertex is its midpoint, a boundary vertex moves to
/// (b1 + 6 v + b2) / 8 of its neighbours along the boundary, so the boundary is the cubic B-spline
/// of its vertices; a triangle touching it is irregular (points on the boundary itself are never
/// inside a regular sub-triangle). Crease edges (Hoppe et al.'s crease rules, given as flags)
/// take the boundary's masks: a vertex on two sharp edges (boundary or crease) moves along them
/// as on a boundary, a vertex on three or more is a corner and stays, and a vertex on one (a dart)
/// is smooth; the limit surface keeps the creases as sharp cubic B-spline curves, and a triangle
/// with a sharp edge at a corner is irregular. The triangles around every corner of an evaluated
/// triangle must
/// be one fan, closed or ending on the boundary: a rank's part can evaluate the triangles whose
/// corners' stars it holds whole (an open fan is taken as the surface's boundary). Serial, not
/// collective.
#include "geom/mesh_topology.hpp"
#include "geom/triangle_mesh.hpp"

#include <cstdint>
#include <span>
#include <vector>

namespace texsim::geom {

/// The functions of one triangle's controls at one point: value and derivatives in s and t.
struct PatchBasisValues {
  std::vector<double> value, d_s, d_t;
};

class LoopPatchBasis {
public:
  /// Deepest subdivision followed for one point: a point within 2^-kMaxDepth of an
  /// extraordinary corner (in s, t) is refused.
  static constexpr int kMaxDepth = 40;

  /// `mesh` consistently oriented; `topology` its adjacency; `creases` 1 per edge of `topology`
  /// that is sharp (geom::crease_edges), or empty for none. All must outlive this object.
  LoopPatchBasis(const TriangleMesh& mesh, const MeshTopology& topology,
                 std::span<const char> creases = {});

  /// Whether the triangles around each corner of triangle t form one fan here, closed or open (a
  /// boundary vertex); not when a vertex is non-manifold (two fans) or only part of its star is
  /// held.
  bool evaluable(std::int32_t t) const;
  /// Three interior corners of valence 6 (t evaluable).
  bool is_regular(std::int32_t t) const;
  /// The controls of triangle t: for a regular triangle the 12 vertices in kRegularPatchLattice
  /// order (corner order of the mesh's triangle), otherwise its corners' 1-rings in a canonical
  /// order (the corners, then each corner's fan counter-clockwise).
  std::vector<std::int32_t> controls(std::int32_t t) const;
  /// The combinatorial structure of triangle t's neighbourhood: its corners' stars in the
  /// numbering of controls(t). Triangles of equal structure have the same functions at the same
  /// (s, t), to the bit (the paper's classes of triangles with equal valences).
  std::vector<std::int32_t> structure(std::int32_t t) const;
  /// The functions of controls(t) at (s, t_param) of triangle t.
  void evaluate(std::int32_t t, double s, double t_param, PatchBasisValues& out) const;

  /// The limit of Loop subdivision at vertex v of per-vertex `values` (`components` per vertex):
  /// (1 - n w) v + w sum of the n neighbours, w = 1 / (n + 3 / (8 beta_n)), inside; on the
  /// boundary (an open fan) (b1 + 4 v + b2) / 6, b1 and b2 its neighbours along the boundary.
  void limit_value(std::int32_t v, std::span<const double> values, int components,
                   std::span<double> out) const;

private:
  /// The triangles around a vertex: one closed fan (inside), one open fan (on the boundary), or
  /// neither (non-manifold, or not all held).
  enum class Fan { kClosed, kOpen, kBroken };

  const TriangleMesh& mesh_;
  const MeshTopology& topology_;
  std::span<const char> creases_;

  Fan fan(std::int32_t v) const;
  /// A boundary or crease edge.
  bool sharp_edge(std::int32_t v, std::int32_t w) const;
};

/// Loop's vertex weight beta_n: an even vertex of valence n moves to (1 - n beta) v + beta sum of
/// its neighbours.
double loop_beta(int valence);

} // namespace texsim::geom
