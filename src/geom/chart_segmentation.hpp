#pragma once
/// Cutting a triangle surface into charts that are topological disks, the pieces a texture atlas
/// flattens one by one.
#include "geom/mesh_topology.hpp"
#include "geom/triangle_mesh.hpp"

#include <cstdint>
#include <span>
#include <vector>

namespace texsim::geom {

/// Limits on the charts segment_charts() grows.
struct ChartSettings {
  /// Most triangles in one chart (>= 1).
  std::int32_t max_chart_triangles = 5000;
  /// Largest angle, in degrees, between a chart triangle's normal and its chart's seed triangle's
  /// normal (0 < value <= 180). Bounds the curvature LSCM has to flatten.
  double max_normal_deviation_degrees = 60.0;
};

/// Charts as a label per triangle.
struct ChartSegmentation {
  std::vector<std::int32_t> chart_of_triangle; ///< chart id of each triangle, 0 .. chart_count-1
  std::int32_t chart_count = 0;
};

/// Splits `mesh` (manifold, consistently oriented, boundaries and any genus allowed) into charts
/// that are topological disks (see is_topological_disk). Charts are grown one at a time: the seed
/// is the lowest-id triangle not yet in a chart, and the chart takes edge-adjacent triangles
/// nearest (centroid distance) to the seed first, ties to the lower triangle id, while the
/// triangle's normal is within the settings' deviation of the seed's, the chart is below the
/// maximum size, and adding the triangle keeps the chart a disk (it shares two edges with the
/// chart, or one edge and its third vertex is new to the chart). A chart that is nevertheless not
/// a disk (a non-manifold vertex) is split with split_chart(). Chart ids follow the order of each
/// chart's smallest triangle id. Deterministic; serial. Throws texsim::Error for invalid settings.
ChartSegmentation segment_charts(const TriangleMesh& mesh, const ChartSettings& settings = {});

/// Cuts the chart made of `chart_triangles` (ids of `mesh`, at least two) into at least two
/// disk-shaped charts: two seeds, the triangle whose centroid is farthest from the lowest-id
/// triangle's and the triangle farthest from that one, grow together by centroid distance under
/// the same disk rule as segment_charts(); triangles neither reaches seed further charts (lowest
/// id first). Returns the pieces, each a list of increasing triangle ids, ordered by their
/// smallest id. `topology` must be that of `mesh`. Deterministic; serial.
std::vector<std::vector<std::int32_t>> split_chart(const TriangleMesh& mesh,
                                                   const MeshTopology& topology,
                                                   std::span<const std::int32_t> chart_triangles);

/// True when the triangles `chart_triangles` of `mesh` form a topological disk: edge-connected,
/// manifold (every edge in at most two of them, one fan at every vertex), with a boundary and
/// Euler characteristic V - E + F = 1 (so genus 0 and exactly one boundary loop). Serial.
bool is_topological_disk(const TriangleMesh& mesh, std::span<const std::int32_t> chart_triangles);

} // namespace texsim::geom
