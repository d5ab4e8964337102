// An image cut into strips of rows, each rank writing its strips as .vti pieces under one .pvti:
// VTK's parallel reader assembles the whole image with every value in place (rows flipped, so
// row 0 of ours is the top row), and the files have the same bytes as those written by a single
// rank holding every strip.
#include "io/parallel_image_data_writer.hpp"
#include "par/comm.hpp"
#include "support/output_files.hpp"

#include <gtest/gtest.h>
#include <vtkDataArray.h>
#include <vtkImageData.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkXMLPImageDataReader.h>

#include <filesystem>

namespace texsim::io {
namespace {

namespace fs = std::filesystem;

constexpr int kWidth = 6, kHeight = 11, kStripRows = 3;

/// This rank's even share of the strips and the rows they cover (with the shared row below).
struct Share {
  int first_strip, count, first_row, end_row;
};

Share share_of(const par::Comm& comm) {
  const int strips = (kHeight + kStripRows - 1) / kStripRows;
  const int first = strips * comm.rank / comm.size, last = strips * (comm.rank + 1) / comm.size;
  return {first, last - first, std::min(first * kStripRows, kHeight),
          last > first ? std::min(last * kStripRows + 1, kHeight) : first * kStripRows};
}

fs::path write_image(const par::Comm& comm, const fs::path& dir) {
  const auto share = share_of(comm);
  std::vector<std::int64_t> ids;
  std::vector<float> uv;
  for (int y = share.first_row; y < share.end_row; ++y)
    for (int x = 0; x < kWidth; ++x) {
      ids.push_back(100 * y + x);
      uv.insert(uv.end(), {float(x) + 0.5f, float(y) + 0.25f});
    }
  return write_parallel_image_data(
      comm, dir, "ids", kWidth, kHeight, kStripRows,
      {share.first_strip,
       share.count,
       {{"id", 1, std::span<const std::int64_t>(ids)}, {"uv", 2, std::span<const float>(uv)}}});
}

TEST(ParallelImageData, StripsAssembleIntoTheWholeImageWithOneRanksBytes) {
  const auto comm = par::world();
  const auto root =
      fs::temp_directory_path() / ("texsim_parallel_image_data_n" + std::to_string(comm.size));
  if (comm.rank == 0)
    fs::remove_all(root);
  comm.barrier();
  const auto pvti = write_image(comm, root / "spread");
  comm.barrier();
  if (comm.rank != 0)
    return;
  write_image({MPI_COMM_SELF, 0, 1}, root / "alone");
  const auto files = test::files_under(root / "alone");
  EXPECT_EQ(files.size(), 5u) << "the .pvti and 4 strips";
  EXPECT_EQ(test::files_under(root / "spread"), files);
  for (const auto& file : files)
    EXPECT_TRUE(test::same_bytes(root / "alone" / file, root / "spread" / file)) << file;

  vtkNew<vtkXMLPImageDataReader> reader;
  reader->SetFileName(pvti.c_str());
  reader->Update();
  auto* image = reader->GetOutput();
  int dims[3];
  image->GetDimensions(dims);
  ASSERT_EQ(dims[0], kWidth);
  ASSERT_EQ(dims[1], kHeight);
  auto* id = image->GetPointData()->GetArray("id");
  auto* uv = image->GetPointData()->GetArray("uv");
  ASSERT_NE(id, nullptr);
  ASSERT_NE(uv, nullptr);
  ASSERT_EQ(id->GetDataTypeSize(), 8);
  for (int j = 0; j < kHeight; ++j)
    for (int x = 0; x < kWidth; ++x) {
      const int y = kHeight - 1 - j; // VTK's row j is our row height - 1 - j
      const vtkIdType at = vtkIdType(j) * kWidth + x;
      EXPECT_EQ(id->GetTuple1(at), 100 * y + x) << x << " " << y;
      EXPECT_EQ(uv->GetComponent(at, 1), float(y) + 0.25f) << x << " " << y;
    }
}

} // namespace
} // namespace texsim::io
