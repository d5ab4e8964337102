// Per-pixel arrays as VTK image data and texture coordinates in surfaces: read back through VTK
// as ParaView reads them, ids above 2^53 exact, rows flipped so row 0 of ours is the top row, and
// a surface's uv marked as its TCoords in the piece and in the .pvtp header.
#include "io/image_data_writer.hpp"
#include "io/parallel_surface_writer.hpp"
#include "par/comm.hpp"

#include <gtest/gtest.h>
#include <vtkDataArray.h>
#include <vtkImageData.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkPolyData.h>
#include <vtkVariant.h>
#include <vtkXMLImageDataReader.h>
#include <vtkXMLPPolyDataReader.h>

#include <filesystem>

namespace texsim::io {
namespace {

TEST(ImageDataWriter, IdsAndRowsRoundTripThroughVtk) {
  const auto comm = par::world();
  if (comm.rank != 0)
    return;
  const int width = 5, height = 3;
  std::vector<std::int64_t> ids;
  std::vector<std::int32_t> ages;
  std::vector<double> uv;
  std::vector<float> weights; // a float field stays Float32, each value exact
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) {
      ids.push_back((std::int64_t{1} << 60) + 10 * y + x);
      ages.push_back(-x * y);
      uv.insert(uv.end(), {x + 0.25, y + 0.75});
      weights.push_back(1.0f / float(3 + 10 * y + x));
    }
  const auto path = std::filesystem::temp_directory_path() / "texsim_image_data_writer.vti";
  write_image_data(path, width, height,
                   {{"id", 1, std::span<const std::int64_t>(ids)},
                    {"age", 1, std::span<const std::int32_t>(ages)},
                    {"uv", 2, std::span<const double>(uv)},
                    {"w", 1, std::span<const float>(weights)}});
  vtkNew<vtkXMLImageDataReader> reader;
  reader->SetFileName(path.c_str());
  reader->Update();
  auto* image = reader->GetOutput();
  int dims[3];
  image->GetDimensions(dims);
  ASSERT_EQ(dims[0], width);
  ASSERT_EQ(dims[1], height);
  auto* id = image->GetPointData()->GetArray("id");
  ASSERT_TRUE(id->GetDataType() == VTK_LONG_LONG || id->GetDataType() == VTK_LONG ||
              id->GetDataType() == VTK_ID_TYPE)
      << "ids must stay 64-bit integers, got type " << id->GetDataType();
  ASSERT_EQ(id->GetDataTypeSize(), 8);
  auto* age = image->GetPointData()->GetArray("age");
  auto* coordinates = image->GetPointData()->GetArray("uv");
  ASSERT_EQ(coordinates->GetNumberOfComponents(), 2);
  auto* weight = image->GetPointData()->GetArray("w");
  ASSERT_EQ(weight->GetDataType(), VTK_FLOAT);
  for (int j = 0; j < height; ++j)
    for (int x = 0; x < width; ++x) {
      const int y = height - 1 - j; // VTK's row j is our row height - 1 - j
      const vtkIdType at = vtkIdType(j) * width + x;
      EXPECT_EQ(id->GetVariantValue(at).ToTypeInt64(), ids[std::size_t(y * width + x)]);
      EXPECT_EQ(age->GetTuple1(at), ages[std::size_t(y * width + x)]);
      EXPECT_EQ(coordinates->GetComponent(at, 1), y + 0.75);
      EXPECT_EQ(float(weight->GetTuple1(at)), weights[std::size_t(y * width + x)]);
    }
  std::filesystem::remove(path);
}

TEST(SurfaceWriter, TextureCoordinatesAreTheSurfacesTCoords) {
  const auto comm = par::world();
  const auto dir = std::filesystem::temp_directory_path() / "texsim_tcoords";
  if (comm.rank == 0)
    std::filesystem::create_directories(dir);
  comm.barrier();
  // Each rank one triangle, uv = (x, y) of its corners.
  const double r = comm.rank;
  const std::vector<double> xyz{r, 0, 0, r + 1, 0, 0, r, 1, 0};
  const std::vector<double> uv{r, 0, r + 1, 0, r, 1};
  const std::vector<std::int64_t> triangles{0, 1, 2};
  SurfacePiece piece{xyz, triangles, {}, {}};
  piece.point_fields.push_back({"uv", 2, std::span<const double>(uv)});
  piece.texture_coordinates = "uv";
  const auto header = write_parallel_surface(comm, dir, "tcoords", piece, SurfaceFormat::vtp);
  comm.barrier();
  if (comm.rank == 0) {
    vtkNew<vtkXMLPPolyDataReader> reader;
    reader->SetFileName(header.c_str());
    reader->Update();
    auto* tcoords = reader->GetOutput()->GetPointData()->GetTCoords();
    ASSERT_NE(tcoords, nullptr);
    EXPECT_STREQ(tcoords->GetName(), "uv");
    ASSERT_EQ(tcoords->GetNumberOfTuples(), 3 * comm.size);
    for (vtkIdType i = 0; i < tcoords->GetNumberOfTuples(); ++i)
      EXPECT_EQ(tcoords->GetComponent(i, 0),
                reader->GetOutput()->GetPoint(i)[0]); // u = x, point by point
    std::filesystem::remove_all(dir);
  }
}

} // namespace
} // namespace texsim::io
