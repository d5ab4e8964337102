#include "vol/vti_io.hpp"

#include "grid_fixtures.hpp"
#include "support/test_data.hpp"

#include <gtest/gtest.h>

#include <fstream>

namespace texsim::vol {
namespace {

using test::input_error_message;

TEST(VtiIo, ScalarRoundTripIsExact) {
  const auto path = texsim::test::scratch_dir("vol_vti_scalar") / "density.vti";
  const ScalarGrid grid = test::odd_scalar_grid(4);
  write_vti(path, grid, "density");
  EXPECT_EQ(std::get<ScalarGrid>(read_vti(path, "density")), grid);
  EXPECT_EQ(std::get<ScalarGrid>(read_vti(path)), grid);
}

TEST(VtiIo, RgbRoundTripIsExact) {
  const auto path = texsim::test::scratch_dir("vol_vti_rgb") / "colour.vti";
  const RgbGrid grid = test::odd_rgb_grid(5);
  write_vti(path, grid, "colour");
  EXPECT_EQ(std::get<RgbGrid>(read_vti(path, "colour")), grid);
}

TEST(VtiIo, ErrorsNameTheFileAndListTheArrays) {
  const auto dir = texsim::test::scratch_dir("vol_vti_errors");
  const auto missing = dir / "missing.vti";
  EXPECT_NE(input_error_message([&] { read_vti(missing); }).find(missing.string()),
            std::string::npos);

  const auto path = dir / "density.vti";
  write_vti(path, test::odd_scalar_grid(6), "density");
  const std::string wrong_name = input_error_message([&] { read_vti(path, "pressure"); });
  EXPECT_NE(wrong_name.find(path.string()), std::string::npos);
  EXPECT_NE(wrong_name.find("'density'"), std::string::npos);

  const auto truncated = dir / "truncated.vti";
  std::filesystem::copy_file(path, truncated);
  std::filesystem::resize_file(truncated, std::filesystem::file_size(path) / 2);
  EXPECT_NE(input_error_message([&] { read_vti(truncated); }).find(truncated.string()),
            std::string::npos);

  const auto garbage = dir / "garbage.vti";
  std::ofstream(garbage) << "not xml at all";
  EXPECT_NE(input_error_message([&] { read_vti(garbage); }).find(garbage.string()),
            std::string::npos);
}

} // namespace
} // namespace texsim::vol
