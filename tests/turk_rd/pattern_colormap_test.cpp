#include "pipelines/turk_rd/pattern_colormap.hpp"
#include "support/input_error.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <string>

namespace texsim::pipelines::turk_rd {
namespace {

using Rgb8 = std::array<std::uint8_t, 3>;

/// Black at 0, pure red at 0.5, (1, 0.6, 0.2) at 1.
PatternColormap three_stop_ramp() {
  return PatternColormap({{0.0, {0.0, 0.0, 0.0}}, {0.5, {1.0, 0.0, 0.0}}, {1.0, {1.0, 0.6, 0.2}}});
}

void expect_rgb_near(const std::array<double, 3>& got, const std::array<double, 3>& want) {
  for (int c = 0; c < 3; ++c)
    EXPECT_NEAR(got[c], want[c], 1e-15) << "component " << c;
}

TEST(PatternColormap, EndpointsAreTheEndColours) {
  const PatternColormap turk(tan_to_dark_stops());
  // lo -> tan (0.93, 0.78, 0.52) * 255, hi -> dark brown (0.12, 0.08, 0.05) * 255, rounded.
  EXPECT_EQ(turk.color(-2.0, -2.0, 3.0), (Rgb8{237, 199, 133}));
  EXPECT_EQ(turk.color(3.0, -2.0, 3.0), (Rgb8{31, 20, 13}));
}

TEST(PatternColormap, InterpolatesLinearlyBetweenStops) {
  const PatternColormap ramp = three_stop_ramp();
  expect_rgb_near(ramp.rgb(0.25), {0.5, 0.0, 0.0});
  expect_rgb_near(ramp.rgb(0.5), {1.0, 0.0, 0.0});
  expect_rgb_near(ramp.rgb(0.75), {1.0, 0.3, 0.1});
  expect_rgb_near(ramp.rgb(0.6), {1.0, 0.12, 0.04});
  // Values: [10, 20] onto [0, 1]; 17.5 -> t = 0.75 -> (255, 76.5, 25.5) rounded half away.
  EXPECT_EQ(ramp.color(17.5, 10.0, 20.0), (Rgb8{255, 77, 26}));
  EXPECT_EQ(ramp.color(15.0, 10.0, 20.0), (Rgb8{255, 0, 0}));
  // Two-stop ramp: the midpoint is the mean colour.
  const PatternColormap two({{0.0, {0.2, 0.4, 1.0}}, {1.0, {0.6, 0.0, 0.2}}});
  expect_rgb_near(two.rgb(0.5), {0.4, 0.2, 0.6});
  EXPECT_EQ(two.color(0.0, -1.0, 1.0), (Rgb8{102, 51, 153}));
}

TEST(PatternColormap, ClampsOutsideTheRange) {
  const PatternColormap ramp = three_stop_ramp();
  EXPECT_EQ(ramp.color(-100.0, 10.0, 20.0), (Rgb8{0, 0, 0}));
  EXPECT_EQ(ramp.color(9.999, 10.0, 20.0), (Rgb8{0, 0, 0}));
  EXPECT_EQ(ramp.color(1e9, 10.0, 20.0), (Rgb8{255, 153, 51}));
  EXPECT_EQ(ramp.color(std::numeric_limits<double>::quiet_NaN(), 10.0, 20.0), (Rgb8{0, 0, 0}));
  // A constant pattern (hi == lo) is a step rather than a division by zero.
  EXPECT_EQ(ramp.color(5.0, 5.0, 5.0), (Rgb8{0, 0, 0}));
  EXPECT_EQ(ramp.color(5.5, 5.0, 5.0), (Rgb8{255, 153, 51}));
  // Stops that do not cover [0, 1] hold their end colours beyond them.
  const PatternColormap inner({{0.25, {0.0, 0.0, 1.0}}, {0.75, {1.0, 1.0, 0.0}}});
  expect_rgb_near(inner.rgb(0.1), {0.0, 0.0, 1.0});
  expect_rgb_near(inner.rgb(0.5), {0.5, 0.5, 0.5});
  expect_rgb_near(inner.rgb(0.9), {1.0, 1.0, 0.0});
}

TEST(PatternColormap, ColorsInterleavesRgb) {
  const PatternColormap ramp = three_stop_ramp();
  const std::vector<double> values = {10.0, 15.0, 20.0, 17.5};
  const auto bytes = ramp.colors(values, 10.0, 20.0);
  ASSERT_EQ(bytes.size(), 12u);
  for (std::size_t i = 0; i < values.size(); ++i) {
    const Rgb8 c = ramp.color(values[i], 10.0, 20.0);
    for (int k = 0; k < 3; ++k)
      EXPECT_EQ(bytes[3 * i + k], c[k]) << "value " << i << " component " << k;
  }
}

TEST(PatternColormap, RejectsBadStops) {
  EXPECT_THROW(PatternColormap(std::vector<ColorStop>{{0.0, {0.0, 0.0, 0.0}}}), Error);
  EXPECT_THROW(PatternColormap({{0.5, {0, 0, 0}}, {0.5, {1, 1, 1}}}), Error);
  EXPECT_THROW(PatternColormap({{0.0, {0, 0, 0}}, {1.5, {1, 1, 1}}}), Error);
  EXPECT_THROW(PatternColormap({{0.0, {0, 0, -0.1}}, {1.0, {1, 1, 1}}}), Error);
}

struct Parsed {
  ConfigDocument document;
  PatternColormap colormap;
};

Parsed parse(const std::string& colors_yaml) {
  auto document = ConfigDocument::parse("turk_rd:\n  render:\n" + colors_yaml, "run.yaml");
  auto colormap = PatternColormap::from_config(document.root().section("turk_rd").section("render"),
                                               tan_to_dark_stops());
  return {std::move(document), std::move(colormap)};
}

TEST(PatternColormap, ReadsEvenlySpacedStopsFromConfig) {
  const Parsed parsed = parse("    colors: [[0, 0, 0], [1, 0.5, 0.25], [1, 1, 1]]\n");
  const auto& stops = parsed.colormap.stops();
  ASSERT_EQ(stops.size(), 3u);
  EXPECT_EQ(stops[0].at, 0.0);
  EXPECT_EQ(stops[1].at, 0.5);
  EXPECT_EQ(stops[2].at, 1.0);
  expect_rgb_near(stops[1].rgb, {1.0, 0.5, 0.25});
  expect_rgb_near(parsed.colormap.rgb(0.75), {1.0, 0.75, 0.625});
  EXPECT_NO_THROW(parsed.document.check_unknown_keys());

  const Parsed block = parse("    colors:\n      - [0.1, 0.2, 0.3]\n      - [0.4, 0.5, 0.6]\n");
  ASSERT_EQ(block.colormap.stops().size(), 2u);
  expect_rgb_near(block.colormap.stops()[1].rgb, {0.4, 0.5, 0.6});
}

TEST(PatternColormap, UsesDefaultStopsWhenKeyIsAbsent) {
  const Parsed parsed = parse("    other: 1\n");
  ASSERT_EQ(parsed.colormap.stops().size(), 2u);
  expect_rgb_near(parsed.colormap.stops()[0].rgb, tan_to_dark_stops()[0].rgb);
  expect_rgb_near(parsed.colormap.stops()[1].rgb, tan_to_dark_stops()[1].rgb);
  EXPECT_THROW(parsed.document.check_unknown_keys(), InputError); // `other` is nobody's key
}

TEST(PatternColormap, BadConfigNamesTheKey) {
  using test::input_error_message;
  const std::string key = "turk_rd.render.colors";
  for (const std::string bad : {"[[0, 0], [1, 1, 1]]", "[[0, 0, 0, 1], [1, 1, 1]]", "[[0, 0, 0]]",
                                "red", "[0, 0, 0]", "[[0, 0, x], [1, 1, 1]]"}) {
    const std::string message = input_error_message([&] { parse("    colors: " + bad + "\n"); });
    EXPECT_NE(message.find(key + ": expected a list of at least 2 [r, g, b] colours"),
              std::string::npos)
        << bad << ": " << message;
  }
  for (const std::string bad : {"[[0, 0, 1.5], [1, 1, 1]]", "[[0, 0, 0], [1, -0.1, 1]]"}) {
    const std::string message = input_error_message([&] { parse("    colors: " + bad + "\n"); });
    EXPECT_NE(message.find(key + ": expected colour components in [0, 1]"), std::string::npos)
        << bad << ": " << message;
  }
}

} // namespace
} // namespace texsim::pipelines::turk_rd
