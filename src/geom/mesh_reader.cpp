#include "geom/mesh_reader.hpp"

#include "core/error.hpp"
#include "geom/off_reader.hpp"

#include <vtkAlgorithm.h>
#include <vtkCallbackCommand.h>
#include <vtkCellArray.h>
#include <vtkCommand.h>
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

/// Collects the error and warning messages VTK objects emit while it is attached, so they reach
/// the caller in an InputError instead of VTK's output window (stderr).
class VtkMessageTrap {
public:
  VtkMessageTrap() {
    callback_->SetClientData(this);
    callback_->SetCallback(&VtkMessageTrap::record);
  }

  void watch(vtkObject* object) {
    object->AddObserver(vtkCommand::ErrorEvent, callback_);
    object->AddObserver(vtkCommand::WarningEvent, callback_);
  }

  const std::vector<std::string>& errors() const { return errors_; }

private:
  static void record(vtkObject*, unsigned long event, void* client, void* call_data) {
    if (event != vtkCommand::ErrorEvent || call_data == nullptr) {
      return;
    }
    std::string message(static_cast<const char*>(call_data));
    // VTK prefixes "ClassName (0x...): "; keep what follows, on one line.
    if (const auto colon = message.find("): "); colon != std::string::npos) {
      message.erase(0, colon + 3);
    }
    std::replace(message.begin(), message.end(), '\n', ' ');
    while (!message.empty() && std::isspace(static_cast<unsigned char>(message.back()))) {
      message.pop_back();
    }
    static_cast<VtkMessageTrap*>(client)->errors_.push_back(message);
  }

  vtkNew<vtkCallbackCommand> callback_;
  std::vector<std::string> errors_;
};

std::string lower_extension(const std::filesystem::path& path) {
  auto ext = path.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return ext;
}

vtkSmartPointer<vtkAlgorithm> make_vtk_reader(const std::string& ext, const std::string& file) {
  if (ext == ".obj") {
    auto reader = vtkSmartPointer<vtkOBJReader>::New();
    reader->SetFileName(file.c_str());
    return reader;
  }
  if (ext == ".ply") {
    auto reader = vtkSmartPointer<vtkPLYReader>::New();
    reader->SetFileName(file.c_str());
    return reader;
  }
  if (ext == ".stl") {
    auto reader = vtkSmartPointer<vtkSTLReader>::New();
    reader->SetFileName(file.c_str());
    reader->MergingOn(); // STL stores each triangle's corners separately; share equal points.
    return reader;
  }
  if (ext == ".vtk") {
    auto reader = vtkSmartPointer<vtkGenericDataObjectReader>::New();
    reader->SetFileName(file.c_str());
    return reader;
  }
  if (ext == ".vtp") {
    auto reader = vtkSmartPointer<vtkXMLPolyDataReader>::New();
    reader->SetFileName(file.c_str());
    return reader;
  }
  if (ext == ".vtu") {
    auto reader = vtkSmartPointer<vtkXMLUnstructuredGridReader>::New();
    reader->SetFileName(file.c_str());
    return reader;
  }
  return nullptr;
}

/// Runs `algorithm`, turning any VTK error into an InputError about `path`.
void update_or_throw(vtkAlgorithm* algorithm, const std::filesystem::path& path,
                     const char* expected) {
  VtkMessageTrap trap;
  trap.watch(algorithm);
  trap.watch(algorithm->GetExecutive());
  algorithm->Update();
  if (!trap.errors().empty() || algorithm->GetErrorCode() != 0) {
    TEXSIM_INPUT_ERROR(path.string()
                       << ": cannot be read as " << expected << " ("
                       << (trap.errors().empty() ? "reader failed" : trap.errors().front()) << ")");
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
