#pragma once
/// A rank's part of a triangle surface with its data, as plain arrays (io does not depend on
/// geom): what the VTK writers take.
#include <cstdint>
#include <span>
#include <string>
#include <vector>

namespace texsim::io {

/// A named array with `components` values per point (or per cell), stored tuple after tuple.
/// Not owned: the caller keeps the values alive while writing.
struct DataField {
  std::string name;
  int components = 1;
  std::span<const double> values;
};

/// Points and triangles of one piece. Not owned.
struct SurfacePiece {
  std::span<const double> xyz;             ///< 3 coordinates per point
  std::span<const std::int64_t> triangles; ///< 3 piece-local point indices per triangle
  std::vector<DataField> point_fields;     ///< values.size() == components * number of points
  std::vector<DataField> cell_fields;      ///< values.size() == components * number of triangles

  std::size_t point_count() const { return xyz.size() / 3; }
  std::size_t triangle_count() const { return triangles.size() / 3; }
};

/// The VTK XML flavour written: .vtp (vtkPolyData) or .vtu (vtkUnstructuredGrid).
enum class SurfaceFormat { vtp, vtu };

} // namespace texsim::io
