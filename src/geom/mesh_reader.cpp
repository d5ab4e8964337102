#include "geom/mesh_reader.hpp"

#include "core/error.hpp"
#include "core/input_file.hpp"
#include "geom/mesh_file_check.hpp"
#include "geom/off_reader.hpp"
#include "vtk/error_capture.hpp"

#include <vtkAlgorithm.h>
#include <vtkCellArray.h>
#include <vtkDataArray.h>
#include <vtkDataSet.h>
#include <vtkExecutive.h>
#include <vtkGenericDataObjectReader.h>
#include <vtkGeometryFilter.h>
#include <vtkIdList.h>
#include <vtkNew.h>
#include <vtkOBJReader.h>
#include <vtkPLYReader.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkSTLReader.h>
#include <vtkSmartPointer.h>
#include <vtkTriangleFilter.h>
#include <vtkXMLPolyDataReader.h>
#include <vtkXMLUnstructuredGridReader.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <limits>
#include <optional>
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

/// A reader of `file`, or of `text_for_vtk` in its place when given (PLY only).
vtkSmartPointer<vtkAlgorithm> make_vtk_reader(const std::string& ext, const std::string& file,
                                              const std::optional<std::string>& text_for_vtk) {
  if (ext == ".obj") {
    return reader_for<vtkOBJReader>(file);
  }
  if (ext == ".ply") {
    auto reader = reader_for<vtkPLYReader>(file);
    if (text_for_vtk) {
      reader->ReadFromInputStringOn();
      reader->SetInputString(*text_for_vtk);
    }
    return reader;
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

/// The file's surface as VTK triangles, point data passed through.
vtkSmartPointer<vtkPolyData>
read_vtk_triangles(const std::filesystem::path& path, const std::string& ext,
                   const std::optional<std::string>& text_for_vtk = std::nullopt) {
  const auto expected = "a " + ext.substr(1) + " mesh file";
  auto reader = make_vtk_reader(ext, path.string(), text_for_vtk);
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
  return triangulate->GetOutput();
}

TriangleMesh to_triangle_mesh(vtkPolyData* triangles, const std::filesystem::path& path) {
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

std::string array_names(vtkPointData* data) {
  std::string names;
  for (int k = 0; k < data->GetNumberOfArrays(); ++k) {
    const char* name = data->GetArrayName(k);
    names += (names.empty() ? "" : ", ") + std::string(name != nullptr ? name : "(unnamed)");
  }
  return names.empty() ? "none" : names;
}

void require_file(const std::filesystem::path& path) {
  require_regular_file(path, std::string("mesh file (") + kKnownExtensions + ")");
}

} // namespace

TriangleMesh read_raw_mesh(const std::filesystem::path& path) {
  const auto ext = lower_extension(path);
  const bool vtk_format = ext == ".obj" || ext == ".ply" || ext == ".stl" || ext == ".vtk" ||
                          ext == ".vtp" || ext == ".vtu";
  if (!vtk_format && ext != ".off") {
    TEXSIM_INPUT_ERROR(shortened(path.string()) << ": unknown mesh extension '" << shortened(ext)
                                                << "'; expected one of " << kKnownExtensions);
  }
  require_file(path);
  // VTK's readers trust what they read: a PLY header larger than its body crashes them.
  const MeshFileCounts counts = check_mesh_file(path);
  std::optional<std::string> text_for_vtk;
  if (counts.ply_needs_final_newline)
    text_for_vtk = read_regular_file(path, "mesh file", UINT64_MAX) + '\n';
  auto mesh = vtk_format ? to_triangle_mesh(read_vtk_triangles(path, ext, text_for_vtk), path)
                         : read_off(path);
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

namespace {

/// The triangles of a .vtk/.vtp/.vtu file and its point data, for reading named arrays.
vtkSmartPointer<vtkPolyData> read_surface_with_arrays(const std::filesystem::path& path) {
  const auto ext = lower_extension(path);
  // VTK's PLY reader keeps only colours, normals and texture coordinates: no named arrays.
  if (ext != ".vtk" && ext != ".vtp" && ext != ".vtu") {
    TEXSIM_INPUT_ERROR(path.string() << ": per-vertex fields are read from .vtp, .vtu and .vtk "
                                        "files (ParaView: File > Save Data), not '"
                                     << ext << "'");
  }
  require_file(path);
  return read_vtk_triangles(path, ext);
}

/// Point array `name` with `components` values per point, checked finite.
std::vector<double> point_array(const std::filesystem::path& path, vtkPointData* data,
                                const std::string& name, int components) {
  vtkDataArray* array = data->GetArray(name.c_str());
  if (array == nullptr || array->GetNumberOfComponents() != components) {
    TEXSIM_INPUT_ERROR(path.string() << ": no " << (components == 1 ? "one" : "three")
                                     << "-component point array '" << name
                                     << "'; the file's point arrays: " << array_names(data));
  }
  std::vector<double> values(std::size_t(array->GetNumberOfTuples()) * std::size_t(components));
  for (vtkIdType i = 0; i < array->GetNumberOfTuples(); ++i)
    for (int c = 0; c < components; ++c) {
      const double value = array->GetComponent(i, c);
      if (!std::isfinite(value)) {
        TEXSIM_INPUT_ERROR(path.string() << ": point array '" << name << "' holds " << value
                                         << " at point " << i << "; expected finite values");
      }
      values[std::size_t(i) * std::size_t(components) + std::size_t(c)] = value;
    }
  return values;
}

TriangleMesh surface_of(const vtkSmartPointer<vtkPolyData>& triangles,
                        const std::filesystem::path& path) {
  auto mesh = to_triangle_mesh(triangles, path);
  if (mesh.triangles.empty()) {
    TEXSIM_INPUT_ERROR(path.string() << ": no triangles; expected a triangle surface");
  }
  return mesh;
}

} // namespace

VertexFields read_vertex_fields(const std::filesystem::path& path,
                                const std::vector<std::string>& names) {
  const auto triangles = read_surface_with_arrays(path);
  VertexFields fields{surface_of(triangles, path), {}};
  for (const auto& name : names)
    fields.values.push_back(point_array(path, triangles->GetPointData(), name, 1));
  return fields;
}

VertexVectors read_vertex_vectors(const std::filesystem::path& path, const std::string& name) {
  const auto triangles = read_surface_with_arrays(path);
  VertexVectors vectors{surface_of(triangles, path), {}};
  const auto values = point_array(path, triangles->GetPointData(), name, 3);
  for (std::size_t i = 0; i + 2 < values.size(); i += 3)
    vectors.values.emplace_back(values[i], values[i + 1], values[i + 2]);
  return vectors;
}

} // namespace texsim::geom
