#include "vol/vdb_io.hpp"

#include "core/error.hpp"
#include "grid_fixtures.hpp"
#include "support/test_data.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <vector>

namespace texsim::vol {
namespace {

using test::input_error_message;

TEST(VdbIo, ScalarRoundTripIsExact) {
  const auto path = texsim::test::scratch_dir("vol_vdb_scalar") / "density.vdb";
  const ScalarGrid grid = test::odd_scalar_grid(1);
  write_vdb(path, grid, "density");
  EXPECT_EQ(std::get<ScalarGrid>(read_vdb(path, "density")), grid);
  EXPECT_EQ(std::get<ScalarGrid>(read_vdb(path)), grid); // first suitable grid
}

TEST(VdbIo, RgbRoundTripIsExact) {
  const auto path = texsim::test::scratch_dir("vol_vdb_rgb") / "colour.vdb";
  const RgbGrid grid = test::odd_rgb_grid(2);
  write_vdb(path, grid, "colour");
  EXPECT_EQ(std::get<RgbGrid>(read_vdb(path, "colour")), grid);
}

TEST(VdbIo, ChannelGridsWriteAsTheirColourOrScalarGrids) {
  const auto dir = texsim::test::scratch_dir("vol_vdb_channels");
  // A channel grid has no spacing or origin: the file says 1 and 0.
  RgbGrid colours = test::odd_rgb_grid(3);
  colours.set_spacing({1.0, 1.0, 1.0});
  colours.set_origin({0.0, 0.0, 0.0});
  write_vdb(dir / "colour.vdb", to_channels(colours), "colour");
  EXPECT_EQ(std::get<RgbGrid>(read_vdb(dir / "colour.vdb", "colour")), colours);
  ScalarGrid density = test::odd_scalar_grid(4);
  density.set_spacing({1.0, 1.0, 1.0});
  density.set_origin({0.0, 0.0, 0.0});
  write_vdb(dir / "density.vdb", to_channels(density), "density");
  EXPECT_EQ(std::get<ScalarGrid>(read_vdb(dir / "density.vdb", "density")), density);
}

TEST(VdbIo, EmptyBoundaryLayersSurviveTheRoundTrip) {
  // Only the centre voxel is non-zero: without the stored dims the active bounding box would
  // shrink the grid to 1 x 1 x 1.
  const auto path = texsim::test::scratch_dir("vol_vdb_sparse") / "sparse.vdb";
  ScalarGrid grid(Dims{9, 4, 6});
  grid.at(4, 2, 3) = 5.0f;
  write_vdb(path, grid, "sparse");
  EXPECT_EQ(std::get<ScalarGrid>(read_vdb(path, "sparse")), grid);
}

TEST(VdbIo, ErrorsNameTheFileAndListTheGrids) {
  const auto dir = texsim::test::scratch_dir("vol_vdb_errors");
  const auto missing = dir / "missing.vdb";
  EXPECT_NE(input_error_message([&] { read_vdb(missing); }).find(missing.string()),
            std::string::npos);

  const auto path = dir / "density.vdb";
  write_vdb(path, test::odd_scalar_grid(3), "density");
  const std::string wrong_name = input_error_message([&] { read_vdb(path, "temperature"); });
  EXPECT_NE(wrong_name.find(path.string()), std::string::npos);
  EXPECT_NE(wrong_name.find("'temperature'"), std::string::npos);
  EXPECT_NE(wrong_name.find("'density'"), std::string::npos);

  const auto truncated = dir / "truncated.vdb";
  std::filesystem::copy_file(path, truncated);
  std::filesystem::resize_file(truncated, std::filesystem::file_size(path) / 2);
  EXPECT_NE(input_error_message([&] { read_vdb(truncated, "density"); }).find(truncated.string()),
            std::string::npos);

  const auto garbage = dir / "garbage.vdb";
  std::ofstream(garbage) << "this is not a VDB file";
  EXPECT_NE(input_error_message([&] { read_vdb(garbage); }).find(garbage.string()),
            std::string::npos);
}

} // namespace
} // namespace texsim::vol
