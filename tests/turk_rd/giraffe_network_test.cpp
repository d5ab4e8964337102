// Turk's giraffe through the binary (4000 cells on a sphere, 2 ranks): the cascade's web between
// the large spots' skirts (patches_a <= 3.45, summary.json network) is one connected network that
// leaves one patch per spot and is thin against the patches, while the background around plain
// spots (a <= 4), read as a web, is as wide as the spots are.
#include "turk_run.hpp"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <string>

namespace texsim {
namespace {

/// The network figures and the first stage's spot count of a two-stage run whose second stage
/// reads `second` (YAML lines).
std::pair<nlohmann::json, int> network_of(const std::string& name, const std::string& second) {
  const auto stages =
      test::turk_stages("turk_rd_giraffe_network", name, 6,
                        "  mesh: {generator: icosphere, level: 4}\n  cells: {count: 4000}\n"
                        "  stages:\n"
                        "    patches: {model: {type: turing_spots, s: 0.0125}, steps: 16000}\n"
                        "    blotches:\n      model: {type: turing_spots, s: 0.2}\n"
                        "      dt: 0.25\n" +
                            second);
  return {stages["blotches"]["network"],
          stages["patches"]["species"]["a"]["regions_above_mean"].get<int>()};
}

TEST(TurkGiraffe, WebIsConnectedThinAndLeavesOnePatchPerSpot) {
  const auto [giraffe, spots] =
      network_of("giraffe", "      steps: 12000\n      active: \"patches_a > 3.45\"\n"
                            "      active_start: initial\n"
                            "      network: {web: \"patches_a <= 3.45\"}\n");
  EXPECT_EQ(giraffe["web_components"].get<int>(), 1);
  EXPECT_GE(giraffe["patches"].get<int>(), spots * 8 / 10) << spots << " spots";
  const double giraffe_ratio =
      giraffe["mean_web_width"].get<double>() / giraffe["median_patch_diameter"].get<double>();
  EXPECT_LT(giraffe_ratio, 0.45);

  const auto [background, _] =
      network_of("spots", "      steps: 10\n      network: {web: \"patches_a <= 4\"}\n");
  const double background_ratio = background["mean_web_width"].get<double>() /
                                  background["median_patch_diameter"].get<double>();
  EXPECT_GT(background_ratio, 0.6) << "plain spots' background is no thin web";
}

} // namespace
} // namespace texsim
