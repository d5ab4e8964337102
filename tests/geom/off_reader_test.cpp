#include "core/error.hpp"
#include "geom/off_reader.hpp"
#include "support/input_error.hpp"
#include "support/test_data.hpp"

#include <gtest/gtest.h>

#include <fstream>

namespace texsim::geom {
namespace {

std::filesystem::path write(const std::string& name, const std::string& text) {
  const auto path = test::scratch_dir("geom_off_reader_" + name) / name;
  std::ofstream(path) << text;
  return path;
}

std::string message_of(const std::filesystem::path& path) {
  return test::input_error_message([&] { read_off(path); });
}

TEST(OffReader, CommentsColoursAndPolygonsAreHandled) {
  const auto path = write("square.off", "# a comment line\n"
                                        "OFF 5 2 0   # counts on the header line\n"
                                        "0 0 0 255 0 0\n"
                                        "1 0 0\n"
                                        "+1 1 0 # trailing comment\n"
                                        "0 1 0\n"
                                        "\n"
                                        "0.5 0.5 1e-1\n"
                                        "4 0 1 2 3 1 1 1\n"
                                        "3 0 1 4\n");
  const auto mesh = read_off(path);
  ASSERT_EQ(mesh.num_vertices(), 5);
  EXPECT_EQ(mesh.positions[2], Vec3(1, 1, 0));
  EXPECT_EQ(mesh.positions[4], Vec3(0.5, 0.5, 0.1));
  // The quad becomes a fan from its first vertex.
  EXPECT_EQ(mesh.triangles, (std::vector<Triangle>{{0, 1, 2}, {0, 2, 3}, {0, 1, 4}}));
}

TEST(OffReader, MalformedFilesNameFileAndLine) {
  const auto bad_header = write("bad_header.off", "OFX\n3 1 0\n");
  EXPECT_EQ(message_of(bad_header), bad_header.string() + ":1: header 'OFX'; expected OFF or COFF");
  const auto bad_number = write("bad_number.off", "OFF\n3 1 0\n0 0 0\n1 zero 0\n0 1 0\n3 0 1 2\n");
  EXPECT_EQ(message_of(bad_number),
            bad_number.string() + ":4: 'zero' where a vertex coordinate was expected");
  const auto truncated = write("truncated.off", "OFF\n3 2 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n");
  EXPECT_EQ(message_of(truncated),
            truncated.string() + ":7: file ends where a face's vertex count was expected");
  EXPECT_NE(message_of(write("n.off", "NOFF\n")).find("variants are not supported"),
            std::string::npos);
  EXPECT_NE(message_of("/nonexistent/x.off").find("/nonexistent/x.off: cannot open"),
            std::string::npos);
}

TEST(OffReaderOnRealData, MalformedFilesAreRefused) {
  for (const std::string name :
       {"models/invalid.off", "models/empty.off", "models/OutOfMemory.off"}) {
    const auto path = test::real_data(name);
    if (path.empty()) {
      GTEST_SKIP() << test::missing_data_message(name);
    }
    const auto message = message_of(path);
    EXPECT_EQ(message.rfind(path.string() + ":", 0), 0u) << message;
  }
  const auto invalid = test::real_data("models/invalid.off");
  EXPECT_EQ(message_of(invalid),
            invalid.string() + ":6: face 0 has 0 vertices; expected a polygon of at least 3");
}

} // namespace
} // namespace texsim::geom
