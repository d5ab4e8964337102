#include "img/gimp_pattern_reader.hpp"

#include "support/input_error.hpp"
#include "support/test_data.hpp"
#include "support/test_files.hpp"

#include <gtest/gtest.h>

#include <cstdint>
#include <string>
#include <vector>

namespace texsim::img {
namespace {

using test::append_u32_big_endian;
using test::Bytes;
using test::input_error_message;
using test::write_bytes;

/// A .pat file assembled field by field as GIMP lays it out.
Bytes pattern_bytes(std::uint32_t width, std::uint32_t height, std::uint32_t bpp,
                    const std::string& name, const Bytes& pixels, std::uint32_t version = 1,
                    const std::string& magic = "GPAT") {
  Bytes out;
  append_u32_big_endian(out, static_cast<std::uint32_t>(24 + name.size() + 1));
  append_u32_big_endian(out, version);
  append_u32_big_endian(out, width);
  append_u32_big_endian(out, height);
  append_u32_big_endian(out, bpp);
  out.insert(out.end(), magic.begin(), magic.end());
  out.insert(out.end(), name.begin(), name.end());
  out.push_back(0);
  out.insert(out.end(), pixels.begin(), pixels.end());
  return out;
}

float unit(int v) {
  return static_cast<float>(v) / 255.0f;
}

TEST(GimpPatternReader, ReadsRgbPatternRowsTopToBottom) {
  const auto dir = test::scratch_dir("img_gimp_rgb");
  // 3 x 2 pixels: row 0 = (10,20,30) (40,50,60) (70,80,90), row 1 = (1,2,3) (4,5,6) (7,8,9).
  const Bytes pixels = {10, 20, 30, 40, 50, 60, 70, 80, 90, 1, 2, 3, 4, 5, 6, 7, 8, 9};
  const GimpPattern pattern =
      read_gimp_pattern(write_bytes(dir / "rgb.pat", pattern_bytes(3, 2, 3, "Wood grain", pixels)));
  EXPECT_EQ(pattern.name, "Wood grain");
  ASSERT_EQ(pattern.image.width(), 3);
  ASSERT_EQ(pattern.image.height(), 2);
  EXPECT_EQ(pattern.image.at(0, 0), (Rgb{unit(10), unit(20), unit(30)}));
  EXPECT_EQ(pattern.image.at(2, 0), (Rgb{unit(70), unit(80), unit(90)}));
  EXPECT_EQ(pattern.image.at(1, 1), (Rgb{unit(4), unit(5), unit(6)}));
}

TEST(GimpPatternReader, GreyAndAlphaVariants) {
  const auto dir = test::scratch_dir("img_gimp_variants");
  const GimpPattern grey =
      read_gimp_pattern(write_bytes(dir / "g.pat", pattern_bytes(2, 1, 1, "g", {0, 255})));
  EXPECT_EQ(grey.image.at(0, 0), Rgb::grey(0.0f));
  EXPECT_EQ(grey.image.at(1, 0), Rgb::grey(1.0f));

  const GimpPattern grey_alpha =
      read_gimp_pattern(write_bytes(dir / "ga.pat", pattern_bytes(2, 1, 2, "ga", {51, 7, 102, 9})));
  EXPECT_EQ(grey_alpha.image.at(0, 0), Rgb::grey(unit(51)));
  EXPECT_EQ(grey_alpha.image.at(1, 0), Rgb::grey(unit(102)));

  const GimpPattern rgba = read_gimp_pattern(
      write_bytes(dir / "rgba.pat", pattern_bytes(1, 2, 4, "rgba", {1, 2, 3, 99, 4, 5, 6, 98})));
  EXPECT_EQ(rgba.image.at(0, 0), (Rgb{unit(1), unit(2), unit(3)}));
  EXPECT_EQ(rgba.image.at(0, 1), (Rgb{unit(4), unit(5), unit(6)}));
}

TEST(GimpPatternReader, MalformedFilesNameTheFileAndTheField) {
  const auto dir = test::scratch_dir("img_gimp_errors");
  const Bytes four(4, 0);
  const auto magic =
      write_bytes(dir / "magic.pat", pattern_bytes(1, 1, 3, "m", {1, 2, 3}, 1, "GBRH"));
  const std::string magic_error = input_error_message([&] { read_gimp_pattern(magic); });
  EXPECT_NE(magic_error.find(magic.string()), std::string::npos);
  EXPECT_NE(magic_error.find("magic"), std::string::npos);

  const auto version = write_bytes(dir / "version.pat", pattern_bytes(1, 1, 3, "v", {1, 2, 3}, 2));
  EXPECT_NE(input_error_message([&] { read_gimp_pattern(version); }).find("version"),
            std::string::npos);

  const auto bpp = write_bytes(dir / "bpp.pat", pattern_bytes(1, 1, 5, "b", {1, 2, 3, 4, 5}));
  EXPECT_NE(input_error_message([&] { read_gimp_pattern(bpp); }).find("bytes per pixel"),
            std::string::npos);

  const auto truncated =
      write_bytes(dir / "truncated.pat", pattern_bytes(4, 4, 3, "t", Bytes(47, 0)));
  const std::string truncated_error = input_error_message([&] { read_gimp_pattern(truncated); });
  EXPECT_NE(truncated_error.find(truncated.string()), std::string::npos);
  EXPECT_NE(truncated_error.find("48"), std::string::npos);

  const auto tiny = write_bytes(dir / "tiny.pat", four);
  EXPECT_NE(input_error_message([&] { read_gimp_pattern(tiny); }).find(tiny.string()),
            std::string::npos);

  const auto missing = dir / "missing.pat";
  EXPECT_NE(input_error_message([&] { read_gimp_pattern(missing); }).find(missing.string()),
            std::string::npos);
}

} // namespace
} // namespace texsim::img
