#include "vol/vti_io.hpp"

#include "core/atomic_output.hpp"
#include "core/input_file.hpp"
#include "vol/grid_checks.hpp"
#include "vtk/error_capture.hpp"

#include <sstream>

#include <vtkExecutive.h>
#include <vtkFloatArray.h>
#include <vtkImageData.h>
#include <vtkInformation.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkStreamingDemandDrivenPipeline.h>
#include <vtkXMLImageDataReader.h>
#include <vtkXMLImageDataWriter.h>
#include <vtkXMLPImageDataReader.h>

namespace texsim::vol {
namespace {

float component(float v, int) {
  return v;
}
float component(const img::Rgb& v, int c) {
  return v[c];
}

template <class T>
void write_grid(const std::filesystem::path& path, const DenseGrid<T>& grid,
                const std::string& array_name, int z_first) {
  const Dims dims = grid.dims();
  const int components = voxel_components<T>;
  vtkNew<vtkImageData> image;
  image->SetExtent(0, dims.nx - 1, 0, dims.ny - 1, z_first, z_first + dims.nz - 1);
  image->SetSpacing(grid.spacing().data());
  image->SetOrigin(grid.origin().data());
  vtkNew<vtkFloatArray> values;
  values->SetName(array_name.c_str());
  values->SetNumberOfComponents(components);
  values->SetNumberOfTuples(static_cast<vtkIdType>(grid.size()));
  for (std::size_t id = 0; id < grid.size(); ++id) { // x-fastest storage is VTK's point order
    for (int c = 0; c < components; ++c) {
      values->SetTypedComponent(static_cast<vtkIdType>(id), c, component(grid.data()[id], c));
    }
  }
  image->GetPointData()->AddArray(values);

  write_atomically(path, [&](const std::filesystem::path& temporary) {
    vtk::ErrorCapture capture;
    vtkNew<vtkXMLImageDataWriter> writer;
    capture.watch(writer);
    writer->SetFileName(temporary.c_str());
    writer->SetInputData(image);
    writer->SetDataModeToAppended();
    writer->SetCompressorTypeToZLib();
    const int ok = writer->Write();
    TEXSIM_VERIFY(ok == 1 && !capture.has_errors(),
                  path.string() << ": cannot write VTK image data: " << capture.errors());
  });
}

template <class T> DenseGrid<T> copy_array(vtkImageData& image, vtkDataArray& array) {
  int n[3];
  image.GetDimensions(n);
  DenseGrid<T> grid(Dims{n[0], n[1], n[2]});
  double spacing[3], origin[3];
  image.GetSpacing(spacing);
  image.GetOrigin(origin);
  grid.set_spacing({spacing[0], spacing[1], spacing[2]});
  grid.set_origin({origin[0], origin[1], origin[2]});
  for (std::size_t id = 0; id < grid.size(); ++id) {
    if constexpr (std::is_same_v<T, float>) {
      grid.data()[id] = static_cast<float>(array.GetComponent(static_cast<vtkIdType>(id), 0));
    } else {
      for (int c = 0; c < 3; ++c) {
        grid.data()[id][c] = static_cast<float>(array.GetComponent(static_cast<vtkIdType>(id), c));
      }
    }
  }
  return grid;
}

} // namespace

void write_vti(const std::filesystem::path& path, const ScalarGrid& grid,
               const std::string& array_name, int z_first) {
  write_grid(path, grid, array_name, z_first);
}

void write_vti(const std::filesystem::path& path, const RgbGrid& grid,
               const std::string& array_name, int z_first) {
  write_grid(path, grid, array_name, z_first);
}

namespace {

template <class Reader>
AnyGrid read_image_data(const std::filesystem::path& path, const std::string& array_name) {
  require_regular_file(path, "VTK image data file (.vti)");
  vtk::ErrorCapture capture;
  vtkNew<Reader> reader;
  capture.watch(reader);
  capture.watch(reader->GetExecutive());
  if (reader->CanReadFile(path.c_str()) == 0) {
    TEXSIM_INPUT_ERROR(path.string() << ": not a VTK XML image data (.vti) file");
  }
  reader->SetFileName(path.c_str());
  // The extent comes from the XML header: check it before VTK allocates the arrays.
  reader->UpdateInformation();
  if (capture.has_errors()) {
    TEXSIM_INPUT_ERROR(path.string() << ": cannot read VTK image data: " << capture.errors());
  }
  const int* extent =
      reader->GetOutputInformation(0)->Get(vtkStreamingDemandDrivenPipeline::WHOLE_EXTENT());
  if (extent != nullptr) {
    const auto points = [&](int axis) {
      return std::int64_t(extent[2 * axis + 1]) - std::int64_t(extent[2 * axis]) + 1;
    };
    require_grid_fits(path, points(0), points(1), points(2), 3 * sizeof(double));
  }
  reader->Update();
  vtkImageData* image = reader->GetOutput();
  if (capture.has_errors() || image == nullptr || image->GetNumberOfPoints() == 0) {
    TEXSIM_INPUT_ERROR(path.string() << ": cannot read VTK image data"
                                     << (capture.has_errors() ? ": " + capture.errors() : ""));
  }
  vtkPointData* points = image->GetPointData();
  std::ostringstream available;
  for (int a = 0; a < points->GetNumberOfArrays(); ++a) {
    const char* name = points->GetArrayName(a);
    available << (a > 0 ? ", " : "") << "'" << (name != nullptr ? name : "") << "'";
  }
  vtkDataArray* array = array_name.empty()
                            ? (points->GetNumberOfArrays() > 0 ? points->GetArray(0) : nullptr)
                            : points->GetArray(array_name.c_str());
  if (array == nullptr) {
    TEXSIM_INPUT_ERROR(path.string()
                       << ": no point-data array"
                       << (array_name.empty() ? "" : " named '" + array_name + "'")
                       << ", the file has "
                       << (points->GetNumberOfArrays() > 0 ? available.str() : "no point arrays"));
  }
  switch (array->GetNumberOfComponents()) {
  case 1:
    return with_finite_voxels(path, copy_array<float>(*image, *array));
  case 3:
    return with_finite_voxels(path, copy_array<img::Rgb>(*image, *array));
  default:
    TEXSIM_INPUT_ERROR(path.string() << ": array '" << array->GetName() << "' has "
                                     << array->GetNumberOfComponents()
                                     << " components, expected 1 (scalar) or 3 (RGB)");
  }
}

} // namespace

AnyGrid read_vti(const std::filesystem::path& path, const std::string& array_name) {
  if (path.extension() == ".pvti")
    return read_image_data<vtkXMLPImageDataReader>(path, array_name);
  return read_image_data<vtkXMLImageDataReader>(path, array_name);
}

} // namespace texsim::vol
