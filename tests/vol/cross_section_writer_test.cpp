#include "vol/cross_section_writer.hpp"

#include "core/error.hpp"
#include "img/image_io.hpp"
#include "support/input_error.hpp"
#include "support/test_data.hpp"

#include <gtest/gtest.h>

#include <cmath>

namespace texsim::vol {
namespace {

/// A 5 x 6 x 7 grid whose every voxel has a distinct colour built from its coordinates.
ChannelGrid coordinate_colours(int channels) {
  ChannelGrid grid({5, 6, 7}, channels);
  for (int k = 0; k < 7; ++k) {
    for (int j = 0; j < 6; ++j) {
      for (int i = 0; i < 5; ++i) {
        auto c = grid.voxel(grid.index(i, j, k));
        c[0] = (i + 0.5f) / 5.0f;
        if (channels == 3) {
          c[1] = (j + 0.5f) / 6.0f;
          c[2] = (k + 0.5f) / 7.0f;
        } else {
          c[0] = (i + 5 * (j + 6 * k) + 0.5f) / 210.0f;
        }
      }
    }
  }
  return grid;
}

/// The largest channel difference between picture pixel (x, y) and voxel (i, j, k).
float difference(const img::RgbImage& picture, int x, int y, const ChannelGrid& grid, int i, int j,
                 int k) {
  const auto voxel = grid.voxel(grid.index(i, j, k));
  const img::Rgb& pixel = picture.at(x, y);
  float worst = 0.0f;
  for (int c = 0; c < 3; ++c) {
    worst = std::max(worst, std::abs(pixel[c] - voxel[grid.channels() == 3 ? c : 0]));
  }
  return worst;
}

TEST(CrossSectionWriter, WrittenPlanesReadBackAsTheSlicesWithinOneLevel) {
  for (const int channels : {1, 3}) {
    const auto dir = test::scratch_dir("vol_cross_sections_" + std::to_string(channels));
    const ChannelGrid grid = coordinate_colours(channels);
    const auto paths = write_cross_sections(dir / "out", "result", grid, {1, 4, 6});
    ASSERT_EQ(paths.size(), 4u);
    EXPECT_EQ(paths[0], dir / "out" / "result_x1.png");
    EXPECT_EQ(paths[1], dir / "out" / "result_y4.png");
    EXPECT_EQ(paths[2], dir / "out" / "result_z6.png");
    EXPECT_EQ(paths[3], dir / "out" / "result_slices.png");
    const img::RgbImage yz = img::read_image(paths[0]);
    const img::RgbImage xz = img::read_image(paths[1]);
    const img::RgbImage xy = img::read_image(paths[2]);
    const img::RgbImage all = img::read_image(paths[3]);
    // YZ: y right, z up; XZ: x right, z up; XY: x right, y up.
    ASSERT_EQ(yz.width(), 6);
    ASSERT_EQ(yz.height(), 7);
    ASSERT_EQ(xz.width(), 5);
    ASSERT_EQ(xz.height(), 7);
    ASSERT_EQ(xy.width(), 5);
    ASSERT_EQ(xy.height(), 6);
    ASSERT_EQ(all.width(), 6 + 4 + 5 + 4 + 5);
    ASSERT_EQ(all.height(), 7);
    constexpr float kLevel = 1.0f / 255.0f;
    for (int k = 0; k < 7; ++k) {
      for (int j = 0; j < 6; ++j) {
        EXPECT_LE(difference(yz, j, 6 - k, grid, 1, j, k), kLevel);
        EXPECT_LE(difference(all, j, 6 - k, grid, 1, j, k), kLevel);
      }
      for (int i = 0; i < 5; ++i) {
        EXPECT_LE(difference(xz, i, 6 - k, grid, i, 4, k), kLevel);
        EXPECT_LE(difference(all, 10 + i, 6 - k, grid, i, 4, k), kLevel);
      }
    }
    for (int j = 0; j < 6; ++j) {
      for (int i = 0; i < 5; ++i) {
        EXPECT_LE(difference(xy, i, 5 - j, grid, i, j, 6), kLevel);
        EXPECT_LE(difference(all, 19 + i, 6 - j, grid, i, j, 6), kLevel); // bottom-aligned
      }
    }
    EXPECT_EQ(all.at(7, 3), img::Rgb::grey(1.0f));  // the gap
    EXPECT_EQ(all.at(20, 0), img::Rgb::grey(1.0f)); // above the shorter XY picture
  }
}

TEST(CrossSectionWriter, ComparisonPutsTheExemplarsCentralSlicesAboveTheResults) {
  const auto dir = test::scratch_dir("vol_cross_section_comparison");
  const ChannelGrid exemplar = coordinate_colours(3); // 5 x 6 x 7
  ChannelGrid result({9, 8, 10}, 3);
  for (std::size_t v = 0; v < result.voxel_count(); ++v)
    result.voxel(v)[1] = float(v % 251) / 251.0f;
  const auto path = write_comparison(dir / "cmp" / "comparison.png", exemplar, result, {3, 2, 1});
  EXPECT_EQ(path, dir / "cmp" / "comparison.png");
  const img::RgbImage picture = img::read_image(path);
  // Rows: exemplar YZ 6 x 7, XZ 5 x 7, XY 5 x 6; result YZ 8 x 10, XZ 9 x 10, XY 9 x 8.
  ASSERT_EQ(picture.width(), 8 + 4 + 9 + 4 + 9);
  ASSERT_EQ(picture.height(), 7 + 4 + 10);
  constexpr float kLevel = 1.0f / 255.0f;
  for (int k = 0; k < 7; ++k)
    for (int j = 0; j < 6; ++j) // the exemplar's x = 2 plane, top left
      EXPECT_LE(difference(picture, j, 6 - k, exemplar, 2, j, k), kLevel);
  for (int j = 0; j < 8; ++j)
    for (int i = 0; i < 9; ++i) // the result's z = 1 plane, bottom right
      EXPECT_LE(difference(picture, 8 + 4 + 9 + 4 + i, 7 + 4 + 2 + 7 - j, result, i, j, 1), kLevel);
  EXPECT_EQ(picture.at(0, 8), img::Rgb::grey(1.0f)); // the gap between the rows
}

TEST(CrossSectionWriter, SectionsFilledPlaneByPlaneInAnyOrderAreTheWholeGridsOnes) {
  for (const int channels : {1, 3}) {
    const ChannelGrid grid = coordinate_colours(channels); // 5 x 6 x 7
    CrossSections sections(grid.dims(), channels, {2, 5, 3});
    const std::size_t plane = 5 * 6 * static_cast<std::size_t>(channels);
    // Planes 4-6, then 0-1, then 2-3: slabs arriving out of order.
    sections.add_planes(4, grid.data().subspan(4 * plane, 3 * plane));
    sections.add_planes(0, grid.data().subspan(0, 2 * plane));
    sections.add_planes(2, grid.data().subspan(2 * plane, 2 * plane));
    for (int axis = 0; axis < 3; ++axis) {
      const img::RgbImage whole = cross_section(grid, axis, sections.positions()[axis]);
      const img::RgbImage& pieces = sections.picture(axis);
      ASSERT_EQ(pieces.width(), whole.width());
      ASSERT_EQ(pieces.height(), whole.height());
      for (int y = 0; y < whole.height(); ++y)
        for (int x = 0; x < whole.width(); ++x)
          EXPECT_EQ(pieces.at(x, y), whole.at(x, y)) << "axis " << axis;
    }
    EXPECT_THROW(sections.add_planes(6, grid.data().subspan(0, 2 * plane)), Error);
  }
}

TEST(CrossSectionWriter, PositionOutsideTheGridIsAnInputError) {
  const auto dir = test::scratch_dir("vol_cross_sections_errors");
  const ChannelGrid grid = coordinate_colours(3);
  EXPECT_EQ(test::input_error_message([&] {
              write_cross_sections(dir, "r", grid, {0, 6, 0});
            }),
            "cross section y = 6 is outside the volume (0 to 5)");
  EXPECT_EQ(test::input_error_message([&] {
              write_cross_sections(dir, "r", grid, {-1, 0, 0});
            }),
            "cross section x = -1 is outside the volume (0 to 4)");
  EXPECT_TRUE(std::filesystem::is_empty(dir));
}

} // namespace
} // namespace texsim::vol
