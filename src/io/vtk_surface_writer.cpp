#include "io/vtk_surface_writer.hpp"

#include "io/vtk_data_array.hpp"

#include "core/atomic_output.hpp"
#include "core/error.hpp"
#include "vtk/error_capture.hpp"

#include <vtkCellArray.h>
#include <vtkCellData.h>
#include <vtkCellType.h>
#include <vtkDoubleArray.h>
#include <vtkIdTypeArray.h>
#include <vtkLZ4DataCompressor.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkSmartPointer.h>
#include <vtkTypeInt32Array.h>
#include <vtkTypeInt64Array.h>
#include <vtkUnstructuredGrid.h>
#include <vtkXMLPolyDataWriter.h>
#include <vtkXMLUnstructuredGridWriter.h>

#include <algorithm>

namespace texsim::io {
namespace {

vtkNew<vtkCellArray> to_vtk_triangles(std::span<const std::int64_t> triangles) {
  static_assert(sizeof(vtkIdType) == sizeof(std::int64_t), "VTK must use 64-bit ids");
  const auto count = static_cast<vtkIdType>(triangles.size() / 3);
  vtkNew<vtkIdTypeArray> offsets;
  offsets->SetNumberOfTuples(count + 1);
  for (vtkIdType i = 0; i <= count; ++i)
    offsets->SetValue(i, 3 * i);
  vtkNew<vtkIdTypeArray> connectivity;
  connectivity->SetNumberOfTuples(static_cast<vtkIdType>(triangles.size()));
  std::copy(triangles.begin(), triangles.end(), connectivity->GetPointer(0));
  vtkNew<vtkCellArray> cells;
  cells->SetData(offsets, connectivity);
  return cells;
}

void add_fields(vtkDataSet& data, const SurfacePiece& piece) {
  for (const auto& field : piece.point_fields) {
    const auto array = to_vtk_array(field);
    if (field.name == piece.texture_coordinates)
      data.GetPointData()->SetTCoords(array);
    else
      data.GetPointData()->AddArray(array);
  }
  for (const auto& field : piece.cell_fields)
    data.GetCellData()->AddArray(to_vtk_array(field));
}

/// Configures `writer` for binary appended LZ4-compressed output, runs it into a temporary file
/// committed over `path`, and turns a VTK error (captured instead of printed to stderr) into
/// texsim::Error naming `path`.
void run_writer(vtkXMLWriter& writer, const std::filesystem::path& path) {
  write_atomically(path, [&](const std::filesystem::path& temporary) {
    vtk::ErrorCapture capture;
    capture.watch(&writer);
    writer.SetFileName(temporary.c_str());
    writer.SetDataModeToAppended();
    writer.EncodeAppendedDataOff();
    writer.SetHeaderTypeToUInt64();
    writer.SetIdTypeToInt64();
    vtkNew<vtkLZ4DataCompressor> compressor;
    writer.SetCompressor(compressor);
    const int ok = writer.Write();
    TEXSIM_VERIFY(ok == 1 && writer.GetErrorCode() == 0,
                  path.string() << ": cannot write VTK file (" << capture.errors() << ")");
  });
}

} // namespace

void check_surface_piece(const SurfacePiece& piece) {
  TEXSIM_VERIFY(piece.xyz.size() % 3 == 0 && piece.triangles.size() % 3 == 0,
                "surface piece: " << piece.xyz.size() << " coordinates and "
                                  << piece.triangles.size()
                                  << " triangle indices are not multiples of 3");
  const auto points = static_cast<std::int64_t>(piece.point_count());
  for (const std::int64_t index : piece.triangles)
    TEXSIM_VERIFY(index >= 0 && index < points,
                  "surface piece: triangle index " << index << " outside [0, " << points << ")");
  const auto check = [](const DataField& field, std::size_t count, const char* what) {
    TEXSIM_VERIFY(field.components >= 1 && field.size() == field.components * count,
                  "surface piece: " << what << " field '" << field.name << "' has " << field.size()
                                    << " values, expected " << field.components << " x " << count);
  };
  for (const auto& field : piece.point_fields)
    check(field, piece.point_count(), "point");
  for (const auto& field : piece.cell_fields)
    check(field, piece.triangle_count(), "cell");
  if (!piece.texture_coordinates.empty()) {
    const auto named = std::find_if(
        piece.point_fields.begin(), piece.point_fields.end(),
        [&](const DataField& field) { return field.name == piece.texture_coordinates; });
    TEXSIM_VERIFY(named != piece.point_fields.end() && named->components == 2,
                  "surface piece: texture coordinates '" << piece.texture_coordinates
                                                         << "' are not a 2-component point field");
  }
}

void write_surface(const std::filesystem::path& path, const SurfacePiece& piece,
                   SurfaceFormat format) {
  check_surface_piece(piece);
  vtkNew<vtkPoints> points;
  points->SetData(to_vtk_array(DataField{"Points", 3, piece.xyz}));
  const auto triangles = to_vtk_triangles(piece.triangles);
  if (format == SurfaceFormat::vtp) {
    vtkNew<vtkPolyData> surface;
    surface->SetPoints(points);
    surface->SetPolys(triangles);
    add_fields(*surface, piece);
    vtkNew<vtkXMLPolyDataWriter> writer;
    writer->SetInputData(surface);
    run_writer(*writer, path);
  } else {
    vtkNew<vtkUnstructuredGrid> surface;
    surface->SetPoints(points);
    surface->SetCells(VTK_TRIANGLE, triangles);
    add_fields(*surface, piece);
    vtkNew<vtkXMLUnstructuredGridWriter> writer;
    writer->SetInputData(surface);
    run_writer(*writer, path);
  }
}

const char* surface_extension(SurfaceFormat format) {
  return format == SurfaceFormat::vtp ? "vtp" : "vtu";
}

} // namespace texsim::io
