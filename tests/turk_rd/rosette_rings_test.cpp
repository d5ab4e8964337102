// Turk's rosettes through the binary (4000 cells on a sphere, 2 ranks): a cascade of large spots
// and then small spots restarted from the uniform state; the small spots shown in the outer band
// of each large spot (4 < large_a < 5.2) close into rings around the lighter centres
// (summary.json rings: most rim sectors marked), while small spots restarted inside whole large
// spots, the cascade's other reading, sit away from the edges.
#include "turk_run.hpp"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <string>

namespace texsim {
namespace {

/// A two-stage cascade through the binary on 4000 cells: large spots, then small spots from the
/// uniform state, shown and measured as `marks` inside the large spots.
nlohmann::json rings_of(const std::string& name, const std::string& active,
                        const std::string& marks) {
  return test::turk_stages(
      "turk_rd_ring_profile", name, 5,
      "  mesh: {generator: icosphere, level: 4}\n  cells: {count: 4000}\n  stages:\n"
      "    large: {model: {type: turing_spots, s: 0.004}, steps: 40000}\n"
      "    rosettes:\n      model: {type: turing_spots, s: 0.05}\n"
      "      dt: 0.5\n      steps: 8000\n      active_start: initial\n" +
          active + "      rings: {regions: \"large_a > 4\", marks: \"" + marks +
          "\"}\n")["rosettes"]["rings"];
}

TEST(TurkRosettes, SmallSpotsInTheOuterBandOfLargeSpotsFormRings) {
  const auto rings = rings_of("band", "", "(large_a < 5.2) * (a > 4.5)");
  EXPECT_GE(rings["regions"].get<int>(), 8);
  EXPECT_GT(rings["rim_marked"].get<double>(), 0.1);
  EXPECT_GT(rings["rim_sectors_marked"].get<double>(), 0.4)
      << "the small spots close around the centres";
  const auto filled = rings_of("filled", "      active: \"large_a > 4\"\n", "a > 4.5");
  EXPECT_LT(filled["rim_sectors_marked"].get<double>(), 0.2)
      << "spots restarted inside whole large spots sit away from their edges";
  EXPECT_GT(filled["centre_marked"].get<double>(), 0.05);
}

} // namespace
} // namespace texsim
