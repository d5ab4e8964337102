#pragma once
/// Halo exchange of scattered points: each rank receives the other ranks' points that lie in the
/// region it needs (its own points' box, or boxes, grown by an interaction radius).
#include "geom/triangle_mesh.hpp"
#include "par/comm.hpp"

#include <cstdint>
#include <limits>
#include <span>
#include <vector>

namespace texsim::geom {

/// A point owned by another rank, as received by exchange_point_halo().
struct HaloPoint {
  std::int64_t id;          ///< global point id
  Vec3 position;            ///< model units
  int owner;                ///< rank that owns the point
  std::int32_t owner_index; ///< index of the point in its owner's owned span
};

/// Closed axis-aligned box [lo, hi]. Empty when lo > hi on some axis (contains nothing).
struct Box3 {
  Vec3 lo = Vec3::Constant(std::numeric_limits<double>::infinity());
  Vec3 hi = Vec3::Constant(-std::numeric_limits<double>::infinity());

  bool empty() const { return (lo.array() > hi.array()).any(); }
  bool contains(const Vec3& p) const {
    return (p.array() >= lo.array()).all() && (p.array() <= hi.array()).all();
  }
  /// The box grown by `margin` on every side; an empty box stays empty.
  Box3 expanded(double margin) const;
  /// Bounding box of the points; the empty box when there are none.
  static Box3 around(std::span<const Vec3> points);
};

/// Collective over comm. Every rank passes its owned points (global ids and positions;
/// owner_index is the position in that span) and the box it needs; returns the OTHER ranks'
/// owned points that lie inside this rank's box, sorted by id. The boxes are allgathered, the
/// points sent with one Alltoallv (each point goes only to the ranks whose box holds it).
std::vector<HaloPoint> exchange_point_halo(const par::Comm& comm,
                                           std::span<const std::int64_t> owned_ids,
                                           std::span<const Vec3> owned_positions,
                                           const Box3& needed);

/// Collective over comm. The same with the needed region a union of boxes (an empty span needs
/// nothing): a point goes to a rank once when any of that rank's boxes holds it. The boxes are
/// allgathered (their number adds up over the ranks: keep it well below the point count, e.g.
/// from covering_boxes()); each rank finds the boxes holding each of its points through a grid
/// index.
std::vector<HaloPoint> exchange_point_halo(const par::Comm& comm,
                                           std::span<const std::int64_t> owned_ids,
                                           std::span<const Vec3> owned_positions,
                                           std::span<const Box3> needed);

/// Per point, 1 when one of `boxes` holds it (through a grid index of the boxes). Serial.
std::vector<char> inside_boxes(std::span<const Vec3> points, std::span<const Box3> boxes);

/// A union of boxes holding every point within `reach` of `positions` and hugging them far more
/// closely than one bounding box (a rank's share of a surface is rarely box-shaped): the
/// bounding box of the points in each occupied cell of a grid with cells of edge `cell`, grown
/// by `reach`, in cell order. Serial; `cell` > 0, `reach` >= 0.
std::vector<Box3> covering_boxes(std::span<const Vec3> positions, double cell, double reach);

} // namespace texsim::geom
