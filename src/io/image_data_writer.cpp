#include "io/image_data_writer.hpp"

#include "core/atomic_output.hpp"
#include "core/error.hpp"
#include "io/vtk_data_array.hpp"
#include "vtk/error_capture.hpp"

#include <vtkImageData.h>
#include <vtkLZ4DataCompressor.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkXMLImageDataWriter.h>

#include <cstring>

namespace texsim::io {

void write_image_data(const std::filesystem::path& path, int width, int height,
                      const std::vector<DataField>& point_fields) {
  write_image_data_piece(path, width, height, 0, height, point_fields);
}

void write_image_data_piece(const std::filesystem::path& path, int width, int height, int first_row,
                            int whole_height, const std::vector<DataField>& point_fields) {
  TEXSIM_VERIFY(width > 0 && height > 0 && first_row >= 0 && first_row + height <= whole_height,
                path.string() << ": rows " << first_row << " .. " << first_row + height - 1
                              << " of " << width << " pixels in an image of " << whole_height
                              << " rows");
  vtkNew<vtkImageData> image;
  // VTK's rows run bottom to top: row y of ours is VTK's whole_height - 1 - y.
  const int vtk_first = whole_height - first_row - height;
  image->SetExtent(0, width - 1, vtk_first, vtk_first + height - 1, 0, 0);
  for (const auto& field : point_fields) {
    TEXSIM_VERIFY(field.size() == std::size_t(field.components) * width * height,
                  path.string() << ": field '" << field.name << "' has " << field.size()
                                << " values for " << width << " x " << height << " pixels");
    auto array = to_vtk_array(field);
    // Flip rows: ours run top to bottom, VTK's bottom to top.
    const auto row_bytes =
        std::size_t(width) * std::size_t(field.components) * std::size_t(array->GetDataTypeSize());
    auto* bytes = static_cast<char*>(array->GetVoidPointer(0));
    std::vector<char> row(row_bytes);
    for (int j = 0; j < height / 2; ++j) {
      char* top = bytes + std::size_t(j) * row_bytes;
      char* bottom = bytes + std::size_t(height - 1 - j) * row_bytes;
      std::memcpy(row.data(), top, row_bytes);
      std::memcpy(top, bottom, row_bytes);
      std::memcpy(bottom, row.data(), row_bytes);
    }
    image->GetPointData()->AddArray(array);
  }
  write_atomically(path, [&](const std::filesystem::path& temporary) {
    vtk::ErrorCapture capture;
    vtkNew<vtkXMLImageDataWriter> writer;
    capture.watch(writer);
    writer->SetFileName(temporary.c_str());
    writer->SetInputData(image);
    writer->SetDataModeToAppended();
    writer->EncodeAppendedDataOff();
    writer->SetHeaderTypeToUInt64();
    vtkNew<vtkLZ4DataCompressor> compressor;
    writer->SetCompressor(compressor);
    const int ok = writer->Write();
    TEXSIM_VERIFY(ok == 1 && writer->GetErrorCode() == 0,
                  path.string() << ": cannot write VTK image (" << capture.errors() << ")");
  });
}

} // namespace texsim::io
