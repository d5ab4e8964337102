#include "vol/inr_reader.hpp"

#include "grid_fixtures.hpp"
#include "support/test_data.hpp"

#include <gtest/gtest.h>

#include <cstring>
#include <fstream>

namespace texsim::vol {
namespace {

using test::input_error_message;

/// An INRIMAGE-4 file written by hand: header lines padded with newlines to 256 bytes, "##}\n",
/// then the raw samples.
void write_inr(const std::filesystem::path& path, const std::string& fields,
               const std::string& raw) {
  std::string header = "#INRIMAGE-4#{\n" + fields;
  header.append(256 - header.size() - 4, '\n');
  header += "##}\n";
  std::ofstream(path, std::ios::binary) << header << raw;
}

std::string little_endian_floats(const ScalarGrid& grid) {
  std::string raw(grid.size() * 4, '\0');
  std::memcpy(raw.data(), grid.data().data(), raw.size()); // the test machine is little-endian
  return raw;
}

TEST(InrReader, HandWrittenFloatVolumeRoundTripsExactly) {
  const auto path = texsim::test::scratch_dir("vol_inr_float") / "small.inr";
  ScalarGrid grid = test::odd_scalar_grid(12);
  grid.set_origin({0.0, 0.0, 0.0});
  write_inr(path,
            "XDIM=5\nYDIM=7\nZDIM=3\nVDIM=1\nTYPE=float\nPIXSIZE=32 bits\nCPU=decm\nVX=0.5\n"
            "VY=0.25\nVZ=1.75\n",
            little_endian_floats(grid));
  EXPECT_EQ(std::get<ScalarGrid>(read_inr(path)), grid);
}

TEST(InrReader, BigEndianUnsignedShortAndRgbBytes) {
  const auto dir = texsim::test::scratch_dir("vol_inr_fixed");
  const auto shorts = dir / "shorts.inr";
  write_inr(shorts, "XDIM=2\nYDIM=1\nZDIM=1\nTYPE=unsigned fixed\nPIXSIZE=16 bits\nCPU=sun\n",
            std::string("\x01\x02\xff\xfe", 4));
  const auto s = std::get<ScalarGrid>(read_inr(shorts));
  EXPECT_EQ(s.at(0, 0, 0), 258.0f);
  EXPECT_EQ(s.at(1, 0, 0), 65534.0f);

  const auto rgb = dir / "rgb.inr";
  write_inr(rgb, "XDIM=1\nYDIM=2\nZDIM=1\nVDIM=3\nTYPE=unsigned fixed\nPIXSIZE=8 bits\nCPU=pc\n",
            std::string("\x0a\x14\x1e\x28\x32\x3c", 6));
  const auto c = std::get<RgbGrid>(read_inr(rgb));
  EXPECT_EQ(c.at(0, 0, 0), (img::Rgb{10, 20, 30}));
  EXPECT_EQ(c.at(0, 1, 0), (img::Rgb{40, 50, 60}));
}

TEST(InrReader, MalformedHeadersNameTheFileAndTheField) {
  const auto dir = texsim::test::scratch_dir("vol_inr_errors");
  const std::string raw(4 * 8, '\0');
  const auto no_zdim = dir / "no_zdim.inr";
  write_inr(no_zdim, "XDIM=2\nYDIM=2\nTYPE=float\nPIXSIZE=32 bits\n", raw);
  const std::string zdim = input_error_message([&] { read_inr(no_zdim); });
  EXPECT_NE(zdim.find(no_zdim.string()), std::string::npos);
  EXPECT_NE(zdim.find("ZDIM"), std::string::npos);

  const auto bad_type = dir / "bad_type.inr";
  write_inr(bad_type, "XDIM=2\nYDIM=2\nZDIM=2\nTYPE=complex\nPIXSIZE=32 bits\n", raw);
  EXPECT_NE(input_error_message([&] { read_inr(bad_type); }).find("TYPE=complex"),
            std::string::npos);

  const auto bad_dim = dir / "bad_dim.inr";
  write_inr(bad_dim, "XDIM=two\nYDIM=2\nZDIM=2\nTYPE=float\nPIXSIZE=32 bits\n", raw);
  EXPECT_NE(input_error_message([&] { read_inr(bad_dim); }).find("XDIM=two"), std::string::npos);

  const auto truncated = dir / "truncated.inr";
  write_inr(truncated, "XDIM=2\nYDIM=2\nZDIM=2\nTYPE=float\nPIXSIZE=32 bits\n", raw.substr(0, 20));
  const std::string short_data = input_error_message([&] { read_inr(truncated); });
  EXPECT_NE(short_data.find(truncated.string()), std::string::npos);
  EXPECT_NE(short_data.find("32"), std::string::npos);

  const auto not_inr = dir / "not_inr.inr";
  std::ofstream(not_inr) << "P6 2 2 255\n";
  EXPECT_NE(input_error_message([&] { read_inr(not_inr); }).find("INRIMAGE-4"), std::string::npos);

  const auto missing = dir / "missing.inr";
  EXPECT_NE(input_error_message([&] { read_inr(missing); }).find(missing.string()),
            std::string::npos);
}

TEST(InrReaderOnRealData, SkullExemplar) {
  const auto path = texsim::test::real_data("volumes/skull_2.9.inr");
  if (path.empty()) {
    GTEST_SKIP() << texsim::test::missing_data_message("volumes/skull_2.9.inr");
  }
  const auto skull = std::get<ScalarGrid>(read_inr(path));
  EXPECT_EQ(skull.dims(), (Dims{64, 64, 64}));
  EXPECT_DOUBLE_EQ(skull.spacing()[0], 3.94305);
  EXPECT_DOUBLE_EQ(skull.spacing()[2], 3.65079);
  float lo = skull.data()[0], hi = lo;
  double sum = 0.0;
  for (float v : skull.data()) {
    ASSERT_TRUE(std::isfinite(v));
    lo = std::min(lo, v);
    hi = std::max(hi, v);
    sum += v;
  }
  // Byte-swapped or misaligned floats would give huge, tiny or negative garbage.
  EXPECT_GE(lo, 0.0f);
  EXPECT_GT(hi, 1.0f);
  EXPECT_LT(hi, 100.0f);
  const double mean = sum / static_cast<double>(skull.size());
  EXPECT_GT(mean, 0.1);
  EXPECT_LT(mean, 0.5 * hi);
}

} // namespace
} // namespace texsim::vol
