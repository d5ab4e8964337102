#include "img/image_io.hpp"

#include "core/rng.hpp"
#include "support/input_error.hpp"
#include "support/test_data.hpp"
#include "support/test_files.hpp"

#include <gtest/gtest.h>

#include <array>
#include <cstdint>
#include <vector>

#include <vtkImageData.h>
#include <vtkNew.h>
#include <vtkPNGReader.h>
#include <vtkPNGWriter.h>
#include <vtkPointData.h>
#include <vtkUnsignedShortArray.h>

namespace texsim::img {
namespace {

using test::append_u32_big_endian;
using test::Bytes;

std::uint32_t crc32(const Bytes& bytes, std::size_t begin) {
  std::uint32_t crc = 0xFFFFFFFFu;
  for (std::size_t i = begin; i < bytes.size(); ++i) {
    crc ^= bytes[i];
    for (int bit = 0; bit < 8; ++bit) {
      crc = (crc >> 1) ^ (0xEDB88320u & (0u - (crc & 1u)));
    }
  }
  return ~crc;
}

void append_chunk(Bytes& png, const char* type, const Bytes& payload) {
  append_u32_big_endian(png, static_cast<std::uint32_t>(payload.size()));
  const std::size_t type_begin = png.size();
  png.insert(png.end(), type, type + 4);
  png.insert(png.end(), payload.begin(), payload.end());
  append_u32_big_endian(png, crc32(png, type_begin));
}

/// A 2 x 2 RGB PNG written byte by byte (zlib stored block, no compression), rows top to bottom:
/// red, green / blue, white. An independent reference for the reader's orientation.
Bytes hand_written_png() {
  Bytes png = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1A, '\n'};
  Bytes header;
  append_u32_big_endian(header, 2);
  append_u32_big_endian(header, 2);
  header.insert(header.end(), {8, 2, 0, 0, 0}); // 8-bit RGB, no interlace
  append_chunk(png, "IHDR", header);
  const Bytes raw = {0, 255, 0, 0, 0, 255, 0, 0, 0, 0, 255, 255, 255, 255}; // filter byte per row
  Bytes zlib = {0x78, 0x01,
                0x01, static_cast<unsigned char>(raw.size()),
                0,    static_cast<unsigned char>(~raw.size()),
                0xFF};
  zlib.insert(zlib.end(), raw.begin(), raw.end());
  std::uint32_t a = 1, b = 0;
  for (unsigned char c : raw) {
    a = (a + c) % 65521;
    b = (b + a) % 65521;
  }
  append_u32_big_endian(zlib, (b << 16) | a);
  append_chunk(png, "IDAT", zlib);
  append_chunk(png, "IEND", {});
  return png;
}

RgbImage random_image(int width, int height, std::uint64_t seed) {
  const CounterRng rng(seed, 1);
  RgbImage image(width, height);
  for (std::size_t i = 0; i < image.size(); ++i) {
    for (int c = 0; c < 3; ++c) {
      image.data()[i][c] = static_cast<float>(rng.uniform(i, 0, static_cast<std::uint32_t>(c)));
    }
  }
  return image;
}

TEST(ImageIo, HandWrittenPngReadsWithRowZeroAtTheTop) {
  const auto path = test::scratch_dir("img_io_orientation") / "quad.png";
  test::write_bytes(path, hand_written_png());
  const RgbImage image = read_image(path);
  ASSERT_EQ(image.width(), 2);
  ASSERT_EQ(image.height(), 2);
  EXPECT_EQ(image.at(0, 0), (Rgb{1, 0, 0}));
  EXPECT_EQ(image.at(1, 0), (Rgb{0, 1, 0}));
  EXPECT_EQ(image.at(0, 1), (Rgb{0, 0, 1}));
  EXPECT_EQ(image.at(1, 1), (Rgb{1, 1, 1}));
}

TEST(ImageIo, WrittenTopLeftPixelReadsBackAtOrigin) {
  const auto path = test::scratch_dir("img_io_top_left") / "top_left.png";
  RgbImage image(7, 4, Rgb::grey(0.0f));
  image.at(0, 0) = Rgb{1, 0, 0};
  write_png(path, image);
  const RgbImage back = read_image(path);
  EXPECT_EQ(back.at(0, 0), (Rgb{1, 0, 0}));
  EXPECT_EQ(back.at(0, 3), Rgb::grey(0.0f));
  EXPECT_EQ(back.at(6, 0), Rgb::grey(0.0f));
}

TEST(ImageIo, PngRoundTripIsExactAfter8BitQuantisation) {
  const auto path = test::scratch_dir("img_io_round_trip") / "random.png";
  const RgbImage image = random_image(37, 23, 11);
  write_png(path, image);
  const RgbImage back = read_image(path);
  EXPECT_EQ(back, quantize_8bit(image));
  EXPECT_NE(back, image); // random floats are not multiples of 1/255: quantisation happened
}

TEST(ImageIo, SixteenBitGreyPngScalesBy65535) {
  const auto path = test::scratch_dir("img_io_16bit") / "grey16.png";
  vtkNew<vtkImageData> data;
  data->SetDimensions(3, 2, 1);
  vtkNew<vtkUnsignedShortArray> values;
  values->SetNumberOfTuples(6);
  const std::array<unsigned short, 6> raw = {0, 1, 300, 40000, 65534, 65535};
  for (vtkIdType i = 0; i < 6; ++i) {
    values->SetValue(i, raw[static_cast<std::size_t>(i)]);
  }
  data->GetPointData()->SetScalars(values);
  vtkNew<vtkPNGWriter> writer;
  writer->SetFileName(path.c_str());
  writer->SetInputData(data);
  writer->Write();

  const RgbImage image = read_image(path);
  ASSERT_EQ(image.width(), 3);
  ASSERT_EQ(image.height(), 2);
  for (int j = 0; j < 2; ++j) {
    for (int i = 0; i < 3; ++i) {
      const float expected =
          static_cast<float>(raw[static_cast<std::size_t>(3 * j + i)]) / 65535.0f;
      EXPECT_EQ(image.at(i, 1 - j), Rgb::grey(expected)); // VTK row 0 is the bottom
    }
  }
}

TEST(ImageIoOnRealData, ReadsGreyPng) {
  const auto path = test::real_data("images/brick.png");
  if (path.empty()) {
    GTEST_SKIP() << test::missing_data_message("images/brick.png");
  }
  const RgbImage image = read_image(path);
  ASSERT_EQ(image.width(), 512);
  ASSERT_EQ(image.height(), 512);
  float lo = 1.0f, hi = 0.0f;
  for (const Rgb& p : image.data()) {
    ASSERT_TRUE(p.r == p.g && p.g == p.b);
    lo = std::min(lo, p.r);
    hi = std::max(hi, p.r);
  }
  EXPECT_GT(hi - lo, 0.5f); // a real photograph, not a constant
}

TEST(ImageIoOnRealData, ReadsPalettePng) {
  const auto path = test::real_data("images/pebbles01.png");
  if (path.empty()) {
    GTEST_SKIP() << test::missing_data_message("images/pebbles01.png");
  }
  const RgbImage image = read_image(path);
  ASSERT_EQ(image.width(), 256);
  ASSERT_EQ(image.height(), 256);
  std::size_t coloured = 0;
  for (const Rgb& p : image.data()) {
    coloured += (p.r != p.g || p.g != p.b) ? 1 : 0;
  }
  EXPECT_GT(coloured, image.size() / 2);
}

TEST(ImageIoOnRealData, ReadsJpegWithWidthAndHeightInOrder) {
  const auto path = test::real_data("models/CWALL02.jpg");
  if (path.empty()) {
    GTEST_SKIP() << test::missing_data_message("models/CWALL02.jpg");
  }
  const RgbImage image = read_image(path);
  EXPECT_EQ(image.width(), 800);
  EXPECT_EQ(image.height(), 446);
  double mean = 0.0;
  for (const Rgb& p : image.data()) {
    mean += (p.r + p.g + p.b) / 3.0;
  }
  mean /= static_cast<double>(image.size());
  EXPECT_GT(mean, 0.05);
  EXPECT_LT(mean, 0.95);
}

TEST(ImageIo, MissingCorruptTruncatedAndUnknownFilesAreInputErrors) {
  const auto dir = test::scratch_dir("img_io_errors");
  const auto missing = dir / "missing.png";
  EXPECT_NE(test::input_error_message([&] { read_image(missing); }).find(missing.string()),
            std::string::npos);

  const auto garbage = dir / "garbage.jpg";
  test::write_bytes(garbage, Bytes(100, 'x'));
  EXPECT_NE(test::input_error_message([&] { read_image(garbage); }).find(garbage.string()),
            std::string::npos);

  const auto truncated = dir / "truncated.png";
  write_png(truncated, random_image(64, 64, 3));
  std::filesystem::resize_file(truncated, std::filesystem::file_size(truncated) / 2);
  EXPECT_NE(test::input_error_message([&] { read_image(truncated); }).find(truncated.string()),
            std::string::npos);

  const auto unknown = dir / "picture.bmp";
  test::write_bytes(unknown, Bytes(10, 0));
  EXPECT_NE(test::input_error_message([&] { read_image(unknown); }).find(".bmp"),
            std::string::npos);
}

TEST(ImageIoOnRealData, TruncatedJpegIsAnInputError) {
  const auto jpeg = test::real_data("models/CWALL02.jpg");
  if (jpeg.empty()) {
    GTEST_SKIP() << test::missing_data_message("models/CWALL02.jpg");
  }
  const auto truncated = test::scratch_dir("img_io_truncated_jpeg") / "truncated.jpg";
  std::filesystem::copy_file(jpeg, truncated);
  std::filesystem::resize_file(truncated, std::filesystem::file_size(jpeg) / 2);
  EXPECT_NE(test::input_error_message([&] { read_image(truncated); }).find(truncated.string()),
            std::string::npos);
}

TEST(WritePng16, KeepsEverySixteenBitValueAndTheRowOrder) {
  const int width = 7, height = 4;
  std::vector<std::uint16_t> values;
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x)
      values.push_back(std::uint16_t(9000 * y + 1000 * x + 65535 % (x + 2)));
  const auto path = std::filesystem::temp_directory_path() / "texsim_png16.png";
  write_png16(path, values, width, height);
  vtkNew<vtkPNGReader> reader;
  reader->SetFileName(path.c_str());
  reader->Update();
  auto* scalars = reader->GetOutput()->GetPointData()->GetScalars();
  ASSERT_EQ(scalars->GetDataType(), VTK_UNSIGNED_SHORT);
  for (int j = 0; j < height; ++j) // VTK's row j is our row height - 1 - j
    for (int x = 0; x < width; ++x)
      EXPECT_EQ(scalars->GetTuple1(vtkIdType(j) * width + x),
                values[std::size_t(height - 1 - j) * width + std::size_t(x)]);
  std::filesystem::remove(path);
}

} // namespace
} // namespace texsim::img
