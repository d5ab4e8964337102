#include "vol/volume_reader.hpp"

#include "grid_fixtures.hpp"
#include "support/test_data.hpp"
#include "vol/hdf5_grid_io.hpp"
#include "vol/vdb_io.hpp"
#include "vol/vti_io.hpp"

#include <gtest/gtest.h>

namespace texsim::vol {
namespace {

TEST(VolumeReader, DispatchesOnExtensionAndKeepsColourExactly) {
  const auto dir = texsim::test::scratch_dir("vol_reader_dispatch");
  const RgbGrid grid = test::odd_rgb_grid(21);
  write_vdb(dir / "a.vdb", grid, "colour");
  write_vti(dir / "b.VTI", grid, "colour");
  write_hdf5_grid(dir / "c.hdf5", grid, "colour");
  EXPECT_EQ(read_volume(dir / "a.vdb"), grid);
  EXPECT_EQ(read_volume(dir / "b.VTI"), grid);
  EXPECT_EQ(read_volume(dir / "c.hdf5"), grid);
}

TEST(VolumeReader, ScalarVolumesBecomeRescaledGrey) {
  const auto path = texsim::test::scratch_dir("vol_reader_grey") / "ramp.h5";
  ScalarGrid ramp(Dims{4, 1, 1});
  for (int i = 0; i < 4; ++i) {
    ramp.at(i, 0, 0) = 10.0f + 2.0f * static_cast<float>(i);
  }
  write_hdf5_grid(path, ramp, "ramp");
  const RgbGrid grey = read_volume(path);
  EXPECT_EQ(grey.at(0, 0, 0), img::Rgb::grey(0.0f));
  EXPECT_EQ(grey.at(2, 0, 0), img::Rgb::grey(4.0f / 6.0f));
  EXPECT_EQ(grey.at(3, 0, 0), img::Rgb::grey(1.0f));
}

TEST(VolumeReader, UnknownExtensionIsAnInputError) {
  const std::string message = test::input_error_message([] { read_volume("exemplar.raw"); });
  EXPECT_NE(message.find("exemplar.raw"), std::string::npos);
  EXPECT_NE(message.find(".vdb"), std::string::npos);
}

TEST(VolumeReaderOnRealData, SkullAsGreyExemplar) {
  const auto path = texsim::test::real_data("volumes/skull_2.9.inr");
  if (path.empty()) {
    GTEST_SKIP() << texsim::test::missing_data_message("volumes/skull_2.9.inr");
  }
  const RgbGrid skull = read_volume(path);
  EXPECT_EQ(skull.dims(), (Dims{64, 64, 64}));
  float hi = 0.0f;
  for (const img::Rgb& v : skull.data()) {
    ASSERT_TRUE(v.r == v.g && v.g == v.b && v.r >= 0.0f && v.r <= 1.0f);
    hi = std::max(hi, v.r);
  }
  EXPECT_EQ(hi, 1.0f);
}

} // namespace
} // namespace texsim::vol
