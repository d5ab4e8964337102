#include "geom/mesh_reader.hpp"

#include "core/error.hpp"
#include "geom/off_reader.hpp"
#include "vtk/error_capture.hpp"

#include <vtkAlgorithm.h>
#include <vtkCellArray.h>
#include <vtkDataSet.h>
#include <vtkExecutive.h>
#include <vtkGenericDataObjectReader.h>
#include <vtkGeometryFilter.h>
#include <vtkIdList.h>
#include <vtkNew.h>
#include <vtkOBJReader.h>
#include <vtkPLYReader.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkSTLReader.h>
#include <vtkSmartPointer.h>
#include <vtkTriangleFilter.h>
#include <vtkXMLPolyDataReader.h>
#include <vtkXMLUnstructuredGridReader.h>

#include <algorithm>
#include <cctype>
#include <limits>
#include <string>
#include <vector>

namespace texsim::geom {
namespace {

constexpr const char* kKnownExtensions = ".obj .ply .stl .vtk .vtp .vtu .off";

std::string lower_extension(const std::filesystem::path& path) {
  auto ext = path.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return ext;
}

template <class Reader> vtkSmartPointer<Reader> reader_for(const std::string& file) {
  auto reader = vtkSmartPointer<Reader>::New();
  reader->SetFileName(file.c_str());
  return reader;
}

vtkSmartPointer<vtkAlgorithm> make_vtk_reader(const std::string& ext, const std::string& file) {
  if (ext == ".obj") {
    return reader_for<vtkOBJReader>(file);
  }
  if (ext == ".ply") {
    return reader_for<vtkPLYReader>(file);
  }
  if (ext == ".stl") {
    auto reader = reader_for<vtkSTLReader>(file);
    reader->MergingOn(); // STL stores each triangle's corners separately; share equal points.
    return reader;
  }
  if (ext == ".vtk") {
    return reader_for<vtkGenericDataObjectReader>(file);
  }
  if (ext == ".vtp") {
    return reader_for<vtkXMLPolyDataReader>(file);
  }
  if (ext == ".vtu") {
    return reader_for<vtkXMLUnstructuredGridReader>(file);
  }
  return nullptr;
}

/// Runs `algorithm`, turning any VTK error into an InputError about `path`.
void update_or_throw(vtkAlgorithm* algorithm, const std::filesystem::path& path,
                     const char* expected) {
  vtk::ErrorCapture capture;
  capture.watch(algorithm);
  capture.watch(algorithm->GetExecutive());
  algorithm->Update();
  if (capture.has_errors() || algorithm->GetErrorCode() != 0) {
    TEXSIM_INPUT_ERROR(
        path.string() << ": cannot be read as " << expected << " ("
                      << (capture.has_errors() ? capture.error_messages().front() : "reader failed")
                      << ")");
  }
}

TriangleMesh read_with_vtk(const std::filesystem::path& path, const std::string& ext) {
  const auto expected = "a " + ext.substr(1) + " mesh file";
  auto reader = make_vtk_reader(ext, path.string());
  update_or_throw(reader, path, expected.c_str());

  auto* dataset = vtkDataSet::SafeDownCast(reader->GetOutputDataObject(0));
  if (dataset == nullptr) {
    TEXSIM_INPUT_ERROR(path.string() << ": holds no VTK dataset; expected " << expected);
  }
  vtkSmartPointer<vtkPolyData> surface = vtkPolyData::SafeDownCast(dataset);
  if (surface == nullptr) {
    vtkNew<vtkGeometryFilter> extract;
    extract->SetInputData(dataset);
    update_or_throw(extract, path, expected.c_str());
    surface = extract->GetOutput();
  }
  vtkNew<vtkTriangleFilter> triangulate;
  triangulate->SetInputData(surface);
  triangulate->PassVertsOff();
  triangulate->PassLinesOff();
  update_or_throw(triangulate, path, expected.c_str());
  vtkPolyData* triangles = triangulate->GetOutput();

  TriangleMesh mesh;
  const vtkIdType n_points = triangles->GetNumberOfPoints();
  if (n_points > std::numeric_limits<std::int32_t>::max()) {
    TEXSIM_INPUT_ERROR(path.string() << ": " << n_points << " points; at most 2^31 - 1 supported");
  }
  mesh.positions.resize(n_points);
  for (vtkIdType i = 0; i < n_points; ++i) {
    triangles->GetPoint(i, mesh.positions[i].data());
  }
  vtkCellArray* polys = triangles->GetPolys();
  mesh.triangles.reserve(polys->GetNumberOfCells());
  vtkNew<vtkIdList> cell;
  for (polys->InitTraversal(); polys->GetNextCell(cell);) {
    if (cell->GetNumberOfIds() == 3) {
      mesh.triangles.push_back({static_cast<std::int32_t>(cell->GetId(0)),
                                static_cast<std::int32_t>(cell->GetId(1)),
                                static_cast<std::int32_t>(cell->GetId(2))});
    }
  }
  return mesh;
}

} // namespace

TriangleMesh read_raw_mesh(const std::filesystem::path& path) {
  const auto ext = lower_extension(path);
  const bool vtk_format = ext == ".obj" || ext == ".ply" || ext == ".stl" || ext == ".vtk" ||
                          ext == ".vtp" || ext == ".vtu";
  if (!vtk_format && ext != ".off") {
    TEXSIM_INPUT_ERROR(path.string() << ": unknown mesh extension '" << ext << "'; expected one of "
                                     << kKnownExtensions);
  }
  std::error_code error;
  if (!std::filesystem::is_regular_file(path, error)) {
    TEXSIM_INPUT_ERROR(path.string()
                       << ": no such file; expected a mesh file (" << kKnownExtensions << ")");
  }
  auto mesh = vtk_format ? read_with_vtk(path, ext) : read_off(path);
  if (mesh.triangles.empty()) {
    TEXSIM_INPUT_ERROR(path.string() << ": no triangles (" << mesh.positions.size()
                                     << " vertices); expected a triangle surface");
  }
  return mesh;
}

TriangleMesh read_mesh(const std::filesystem::path& path, const MeshRepairOptions& options,
                       RepairReport* report) {
  auto mesh = read_raw_mesh(path);
  const auto repaired = repair(mesh, options, path.string());
  if (report != nullptr) {
    *report = repaired;
  }
  return mesh;
}

} // namespace texsim::geom
