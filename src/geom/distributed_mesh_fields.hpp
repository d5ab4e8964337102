#pragma once
/// A mesh file's point arrays (`<pipeline>.mesh_fields`) sampled at points spread over ranks,
/// with only rank 0 reading and holding the file (it holds the input surface anyway).
///
/// Each sample() call, rank 0 sends every rank the file's triangles whose bounding boxes come
/// within a margin of the box of that rank's points; the rank samples at the closest point among
/// them. A rank whose points lie farther from its triangles than the margin asks again with the
/// largest such distance over the ranks as the margin: then every point's closest triangle of the
/// whole file is among those it holds (the closest point found is no nearer than the true one), so
/// the values are the whole file's, up to the choice between equally close triangles at a shared
/// edge or corner (rounding). Ranks hold O(their part of the file).
#include "geom/mesh_reader.hpp"
#include "geom/mesh_source.hpp"
#include "geom/surface_field_sampler.hpp"
#include "par/comm.hpp"

#include <Eigen/Geometry>

#include <optional>
#include <span>
#include <string>
#include <vector>

namespace texsim::geom {

class DistributedMeshFields {
public:
  /// Rank 0 reads the arrays `names` of `mesh.file` on its surface scaled by `mesh.scale`.
  /// Collective; InputError on every rank naming the file for a missing array or a format
  /// without arrays.
  DistributedMeshFields(const par::Comm& comm, const MeshSource& mesh,
                        const std::vector<std::string>& names);

  const par::Comm& comm() const { return comm_; }
  std::size_t field_count() const { return field_count_; }

  /// Field k at each of this rank's points: result[k][i]. Collective.
  std::vector<std::vector<double>> sample(std::span<const Vec3> points) const;

private:
  par::Comm comm_;
  std::size_t field_count_ = 0;
  double initial_margin_ = 0;                       ///< 1% of the file's bounding-box diagonal
  std::optional<VertexFields> file_;                ///< rank 0 only
  std::vector<Eigen::AlignedBox3d> triangle_boxes_; ///< rank 0 only

  /// The file's triangles near `box` grown by `margin`, with their vertices and values, packed
  /// as [vertices, triangles, fields, whole file (0/1), xyz..., corners..., values...].
  std::vector<double> crop(const Eigen::AlignedBox3d& box, double margin) const;
};

} // namespace texsim::geom
