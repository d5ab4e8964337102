#pragma once
/// A rank's part of a triangle surface with its data, as plain arrays (io does not depend on
/// geom): what the VTK writers take.
#include <cstdint>
#include <span>
#include <string>
#include <variant>
#include <vector>

namespace texsim::io {

/// The values of a field: real numbers are written as Float64, or as Float32 when they are
/// floats already (half the bytes); ids, ranks and other integers keep their integer type (Int32
/// or Int64), so ParaView colours and thresholds them exactly.
using FieldValues = std::variant<std::span<const double>, std::span<const std::int32_t>,
                                 std::span<const std::int64_t>, std::span<const float>>;

/// A named array with `components` values per point (or per cell), stored tuple after tuple.
/// Not owned: the caller keeps the values alive while writing.
struct DataField {
  std::string name;
  int components = 1;
  FieldValues values;

  /// Number of values (components x tuples).
  std::size_t size() const {
    return std::visit([](const auto& span) { return span.size(); }, values);
  }
  /// Tuples [first, first + count) of the field, with its name and components.
  DataField tuples(std::size_t first, std::size_t count) const {
    const auto part = [&](const auto& span) -> FieldValues {
      return span.subspan(first * std::size_t(components), count * std::size_t(components));
    };
    return {name, components, std::visit(part, values)};
  }
  /// The VTK XML type name of the values: "Float64", "Int32", "Int64" or "Float32".
  const char* vtk_type_name() const {
    constexpr const char* names[] = {"Float64", "Int32", "Int64", "Float32"};
    return names[values.index()];
  }
};

/// Points and triangles of one piece. Not owned.
struct SurfacePiece {
  std::span<const double> xyz;             ///< 3 coordinates per point
  std::span<const std::int64_t> triangles; ///< 3 piece-local point indices per triangle
  std::vector<DataField> point_fields{};   ///< values.size() == components * number of points
  std::vector<DataField> cell_fields{};    ///< values.size() == components * number of triangles
  /// Name of a 2-component point field to mark as the texture coordinates (VTK's TCoords), so
  /// ParaView maps a texture image with it; empty: none.
  std::string texture_coordinates{};

  std::size_t point_count() const { return xyz.size() / 3; }
  std::size_t triangle_count() const { return triangles.size() / 3; }
};

/// The VTK XML flavour written: .vtp (vtkPolyData) or .vtu (vtkUnstructuredGrid).
enum class SurfaceFormat { vtp, vtu };

} // namespace texsim::io
