#include "vol/hdf5_grid_io.hpp"

#include "grid_fixtures.hpp"
#include "support/test_data.hpp"

#include <gtest/gtest.h>

#include <fstream>

namespace texsim::vol {
namespace {

using test::input_error_message;

TEST(Hdf5GridIo, ScalarRoundTripIsExact) {
  const auto path = texsim::test::scratch_dir("vol_h5_scalar") / "density.h5";
  const ScalarGrid grid = test::odd_scalar_grid(7);
  write_hdf5_grid(path, grid, "density");
  EXPECT_EQ(std::get<ScalarGrid>(read_hdf5_grid(path, "density")), grid);
  EXPECT_EQ(std::get<ScalarGrid>(read_hdf5_grid(path)), grid);
}

TEST(Hdf5GridIo, RgbRoundTripIsExact) {
  const auto path = texsim::test::scratch_dir("vol_h5_rgb") / "colour.h5";
  const RgbGrid grid = test::odd_rgb_grid(8);
  write_hdf5_grid(path, grid, "colour");
  EXPECT_EQ(std::get<RgbGrid>(read_hdf5_grid(path, "colour")), grid);
}

TEST(Hdf5GridIo, ErrorsNameTheFileAndDataset) {
  const auto dir = texsim::test::scratch_dir("vol_h5_errors");
  const auto missing = dir / "missing.h5";
  EXPECT_NE(input_error_message([&] { read_hdf5_grid(missing); }).find(missing.string()),
            std::string::npos);

  const auto path = dir / "density.h5";
  write_hdf5_grid(path, test::odd_scalar_grid(9), "density");
  const std::string wrong_name = input_error_message([&] { read_hdf5_grid(path, "velocity"); });
  EXPECT_NE(wrong_name.find(path.string()), std::string::npos);
  EXPECT_NE(wrong_name.find("'velocity'"), std::string::npos);
  EXPECT_NE(wrong_name.find("'density'"), std::string::npos);

  const auto truncated = dir / "truncated.h5";
  std::filesystem::copy_file(path, truncated);
  std::filesystem::resize_file(truncated, std::filesystem::file_size(path) - 200);
  EXPECT_NE(input_error_message([&] { read_hdf5_grid(truncated); }).find(truncated.string()),
            std::string::npos);

  const auto garbage = dir / "garbage.h5";
  std::ofstream(garbage) << "plain text";
  EXPECT_NE(input_error_message([&] { read_hdf5_grid(garbage); }).find(garbage.string()),
            std::string::npos);
}

} // namespace
} // namespace texsim::vol
