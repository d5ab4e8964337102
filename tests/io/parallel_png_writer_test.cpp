// PNG files whose rows are spread over ranks: libpng (through VTK's reader) decodes every pixel
// back exactly, 8-bit RGB and 16-bit grey, and zlib inflates the IDAT stream with its checksum
// (libpng does not check it); the file has the same bytes as one written by a single
// rank holding every row; a smooth image really is compressed; rows that do not tile the image
// are one clear error on every rank.
#include "core/error.hpp"
#include "io/parallel_png_writer.hpp"
#include "par/comm.hpp"

#include <gtest/gtest.h>
#include <vtkDataArray.h>
#include <vtkImageData.h>
#include <vtkNew.h>
#include <vtkPNGReader.h>
#include <vtkPointData.h>
#include <zlib.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>

namespace texsim::io {
namespace {

namespace fs = std::filesystem;

constexpr int kWidth = 37, kHeight = 29, kSegmentRows = 4;

/// An empty directory for this test at this rank count (the ctests of 1, 2, 3 ranks may run at
/// once).
fs::path scratch(const par::Comm& comm, const std::string& name) {
  const auto dir = fs::temp_directory_path() / (name + "_n" + std::to_string(comm.size));
  if (comm.rank == 0) {
    fs::remove_all(dir);
    fs::create_directories(dir);
  }
  comm.barrier();
  return dir;
}

/// Gradients, edges and a little hashed noise, so every PNG filter wins somewhere.
std::vector<std::uint8_t> test_pixels(PngPixels pixels) {
  const int bpp = pixels == PngPixels::rgb8 ? 3 : 2;
  std::vector<std::uint8_t> bytes;
  for (int y = 0; y < kHeight; ++y)
    for (int x = 0; x < kWidth; ++x)
      for (int c = 0; c < bpp; ++c) {
        const unsigned noise =
            (unsigned(x) * 73856093u ^ unsigned(y) * 19349663u ^ unsigned(c) * 83492791u) % 7u;
        bytes.push_back(std::uint8_t((x > 20 ? 200 : 0) + 3 * x + 5 * y * (c + 1) +
                                     (y % 9 == 0 ? int(noise) * 30 : 0)));
      }
  return bytes;
}

/// This rank's share of the segments, in rank order, as write_parallel_png wants its rows.
PngRows share(const par::Comm& comm, const std::vector<std::uint8_t>& image, PngPixels pixels) {
  const auto row_bytes = std::size_t(kWidth) * (pixels == PngPixels::rgb8 ? 3 : 2);
  const int segments = (kHeight + kSegmentRows - 1) / kSegmentRows;
  const int first = std::min(kHeight, segments * comm.rank / comm.size * kSegmentRows);
  const int last = std::min(kHeight, segments * (comm.rank + 1) / comm.size * kSegmentRows);
  PngRows rows{first, last - first, {}, {}};
  rows.pixels = std::span(image).subspan(std::size_t(first) * row_bytes,
                                         std::size_t(last - first) * row_bytes);
  if (first > 0 && last > first)
    rows.above = std::span(image).subspan(std::size_t(first - 1) * row_bytes, row_bytes);
  return rows;
}

/// The PNG's values as libpng decodes them, top row first.
std::vector<unsigned> decoded(const fs::path& png, int* components) {
  vtkNew<vtkPNGReader> reader;
  reader->SetFileName(png.c_str());
  reader->Update();
  auto* image = reader->GetOutput();
  int dims[3];
  image->GetDimensions(dims);
  EXPECT_EQ(dims[0], kWidth);
  EXPECT_EQ(dims[1], kHeight);
  auto* scalars = image->GetPointData()->GetScalars();
  *components = scalars->GetNumberOfComponents();
  std::vector<unsigned> values;
  for (int y = 0; y < kHeight; ++y) // VTK's rows run bottom to top
    for (int x = 0; x < kWidth; ++x)
      for (int c = 0; c < *components; ++c)
        values.push_back(
            unsigned(scalars->GetComponent(vtkIdType(kHeight - 1 - y) * kWidth + x, c)));
  return values;
}

std::string bytes_of(const fs::path& file) {
  std::ifstream in(file, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), {}};
}

std::uint32_t big_endian_u32(const std::string& bytes, std::size_t at) {
  std::uint32_t value = 0;
  for (std::size_t i = 0; i < 4; ++i)
    value = value << 8 | std::uint8_t(bytes[at + i]);
  return value;
}

/// Checks every chunk's CRC-32 and inflates the IDAT chunks' concatenation as one zlib stream,
/// which zlib accepts only with the right Adler-32 sum at its end; returns its length.
std::size_t inflated_length(const fs::path& png) {
  const auto bytes = bytes_of(png);
  std::string stream;
  for (std::size_t at = 8; at + 12 <= bytes.size();) {
    const auto length = big_endian_u32(bytes, at);
    const auto* typed = reinterpret_cast<const Bytef*>(bytes.data() + at + 4);
    EXPECT_EQ(crc32(0, typed, uInt(length + 4)), big_endian_u32(bytes, at + 8 + length))
        << bytes.substr(at + 4, 4) << " chunk at " << at;
    if (bytes.compare(at + 4, 4, "IDAT") == 0)
      stream += bytes.substr(at + 8, length);
    at += 12 + length;
  }
  std::vector<Bytef> out(4 * std::size_t(kWidth) * kHeight + kHeight + 1024);
  uLongf out_length = uLongf(out.size());
  EXPECT_EQ(uncompress(out.data(), &out_length, reinterpret_cast<const Bytef*>(stream.data()),
                       uLong(stream.size())),
            Z_OK);
  return out_length;
}

class ParallelPng : public ::testing::TestWithParam<PngPixels> {};

TEST_P(ParallelPng, DecodesToThePixelsAndMatchesOneRanksBytes) {
  const auto comm = par::world();
  const auto pixels = GetParam();
  const auto dir = scratch(comm, "texsim_parallel_png");
  const auto image = test_pixels(pixels);
  write_parallel_png(comm, dir / "spread.png", kWidth, kHeight, pixels, share(comm, image, pixels),
                     kSegmentRows, comm.size - 1);
  comm.barrier();
  if (comm.rank != 0)
    return;
  const par::Comm self{MPI_COMM_SELF, 0, 1};
  write_parallel_png(self, dir / "alone.png", kWidth, kHeight, pixels, share(self, image, pixels),
                     kSegmentRows);
  EXPECT_EQ(bytes_of(dir / "spread.png"), bytes_of(dir / "alone.png"));
  const std::size_t bpp = pixels == PngPixels::rgb8 ? 3 : 2;
  EXPECT_EQ(inflated_length(dir / "spread.png"), std::size_t(kHeight) * (1 + kWidth * bpp));
  int components = 0;
  const auto values = decoded(dir / "spread.png", &components);
  if (pixels == PngPixels::rgb8) {
    ASSERT_EQ(components, 3);
    EXPECT_EQ(values, std::vector<unsigned>(image.begin(), image.end()));
  } else {
    ASSERT_EQ(components, 1);
    std::vector<unsigned> expected;
    for (std::size_t i = 0; i < image.size(); i += 2)
      expected.push_back(unsigned(image[i]) << 8 | image[i + 1]);
    EXPECT_EQ(values, expected);
  }
}

INSTANTIATE_TEST_SUITE_P(Pixels, ParallelPng,
                         ::testing::Values(PngPixels::rgb8, PngPixels::grey16));

TEST(ParallelPngFile, ASmoothImageIsCompressed) {
  const auto comm = par::world();
  const auto dir = scratch(comm, "texsim_parallel_png_smooth");
  std::vector<std::uint8_t> image;
  for (int y = 0; y < kHeight; ++y)
    for (int x = 0; x < kWidth; ++x)
      image.insert(image.end(), {std::uint8_t(x), std::uint8_t(y), 128});
  write_parallel_png(comm, dir / "smooth.png", kWidth, kHeight, PngPixels::rgb8,
                     share(comm, image, PngPixels::rgb8), kSegmentRows);
  if (comm.rank == 0) {
    EXPECT_LT(fs::file_size(dir / "smooth.png"), image.size() / 4);
  }
}

TEST(ParallelPngFile, RowsThatDoNotTileTheImageAreAnErrorOnEveryRank) {
  const auto comm = par::world();
  const auto dir = scratch(comm, "texsim_parallel_png_gap");
  const auto image = test_pixels(PngPixels::rgb8);
  auto rows = share(comm, image, PngPixels::rgb8);
  if (comm.rank == comm.size - 1) { // the last row is missing
    rows.count -= 1;
    rows.pixels = rows.pixels.first(rows.pixels.size() - std::size_t(kWidth) * 3);
  }
  try {
    write_parallel_png(comm, dir / "gap.png", kWidth, kHeight, PngPixels::rgb8, rows, kSegmentRows);
    FAIL() << "no error";
  } catch (const Error& error) {
    EXPECT_NE(std::string(error.what()).find("gap.png"), std::string::npos) << error.what();
    EXPECT_NE(std::string(error.what()).find("28 of 29 rows"), std::string::npos) << error.what();
  }
  EXPECT_FALSE(fs::exists(dir / "gap.png"));
}

} // namespace
} // namespace texsim::io
