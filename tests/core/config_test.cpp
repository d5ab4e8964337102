#include "core/config.hpp"
#include "support/input_error.hpp"

#include <gtest/gtest.h>

#include <cstdlib>
#include <string>

namespace texsim {
namespace {

TEST(Config, ReadsTypedValuesAndDefaults) {
  auto document = ConfigDocument::parse("a: 1.5\nb: {c: 3, d: [1, 2, 3]}\nname: x\n", "t.yaml");
  auto root = document.root();
  EXPECT_DOUBLE_EQ(root.get<double>("a", 0.0), 1.5);
  EXPECT_EQ(root.section("b").get<int>("c", 0), 3);
  EXPECT_EQ(root.section("b").get<std::vector<double>>("d", {}), (std::vector<double>{1, 2, 3}));
  EXPECT_EQ(root.get<std::string>("name", ""), "x");
  EXPECT_EQ(root.get<int>("absent", 7), 7);
  EXPECT_NO_THROW(document.check_unknown_keys());
}

TEST(Config, DataDirectoryComesFromTexsimDataOrDefaultsToData) {
  const std::string text = "mesh: {file: \"${TEXSIM_DATA}/meshes/a.off\"}\n"
                           "images: [\"${TEXSIM_DATA}/x.png:${TEXSIM_DATA}/y.png\"]\n";
  ::unsetenv("TEXSIM_DATA");
  auto by_default = ConfigDocument::parse(text, "t.yaml");
  EXPECT_EQ(by_default.root().section("mesh").get<std::string>("file", ""), "data/meshes/a.off");
  ::setenv("TEXSIM_DATA", "/opt/texsim/share/texsim/data", 1);
  auto installed = ConfigDocument::parse(text, "t.yaml");
  installed.set_override("extra=${TEXSIM_DATA}/b.off");
  ::unsetenv("TEXSIM_DATA");
  EXPECT_EQ(installed.root().section("mesh").get<std::string>("file", ""),
            "/opt/texsim/share/texsim/data/meshes/a.off");
  EXPECT_EQ(installed.root().get<std::vector<std::string>>("images", {}),
            (std::vector<std::string>{
                "/opt/texsim/share/texsim/data/x.png:/opt/texsim/share/texsim/data/y.png"}));
  EXPECT_EQ(installed.root().get<std::string>("extra", ""), "/opt/texsim/share/texsim/data/b.off");
  // Every rank parses the emitted text: it holds the paths, not the variable.
  EXPECT_EQ(installed.emit().find("TEXSIM_DATA"), std::string::npos) << installed.emit();
}

TEST(Config, ErrorNamesKeyPathExpectationAndValue) {
  auto document = ConfigDocument::parse("fem_rd: {time: {dt: -0.1}}", "t.yaml");
  const auto time = document.root().section("fem_rd").section("time");
  EXPECT_EQ(test::input_error_message([&] { time.get<double>("dt", 1.0, positive()); }),
            "fem_rd.time.dt: expected a positive number, got -0.1");
}

TEST(Config, WrongTypeIsAnError) {
  auto document = ConfigDocument::parse("steps: ten\nlevel: 2.5\nflag: maybe", "t.yaml");
  auto root = document.root();
  EXPECT_EQ(test::input_error_message([&] { root.get<int>("steps", 1); }),
            "steps: expected an integer, got ten");
  EXPECT_EQ(test::input_error_message([&] { root.get<int>("level", 1); }),
            "level: expected an integer, got 2.5");
  EXPECT_EQ(test::input_error_message([&] { root.get<bool>("flag", false); }),
            "flag: expected true or false, got maybe");
}

TEST(Config, MissingRequiredKey) {
  auto document = ConfigDocument::parse("{}", "t.yaml");
  EXPECT_EQ(test::input_error_message([&] { document.root().require<std::string>("pipeline"); }),
            "pipeline: expected a string (required key is missing), got nothing");
}

TEST(Config, UnknownKeySuggestsNearestKnownKey) {
  auto document = ConfigDocument::parse("solver: {tolerance: 1e-8, max_iters: 10}", "run.yaml");
  const auto solver = document.root().section("solver");
  solver.get<double>("tolerance", 1e-6);
  solver.get<int>("max_iterations", 100);
  EXPECT_EQ(test::input_error_message([&] { document.check_unknown_keys(); }),
            "run.yaml: unknown key 'solver.max_iters' (did you mean 'solver.max_iterations'?)");
}

TEST(Config, UnknownKeyWithoutCloseMatchListsKnownKeys) {
  auto document = ConfigDocument::parse("alpha: 1\nzzzzzz: 2", "run.yaml");
  document.root().get<int>("alpha", 0);
  EXPECT_EQ(test::input_error_message([&] { document.check_unknown_keys(); }),
            "run.yaml: unknown key 'zzzzzz'; known keys here: alpha");
}

TEST(Config, ChoiceMapsStringsToEnums) {
  enum class Model { kSpots, kStripes };
  auto document = ConfigDocument::parse("model: stripes\nbad: waves", "t.yaml");
  auto root = document.root();
  const std::vector<std::pair<std::string, Model>> options = {{"spots", Model::kSpots},
                                                              {"stripes", Model::kStripes}};
  EXPECT_EQ(root.choice("model", Model::kSpots, options), Model::kStripes);
  EXPECT_EQ(test::input_error_message([&] { root.choice("bad", Model::kSpots, options); }),
            "bad: expected one of spots, stripes, got waves");
}

TEST(Config, OverridesCreateAndReplaceKeysAndAreValidatedTheSameWay) {
  auto document = ConfigDocument::parse("time: {dt: 0.1}", "t.yaml");
  document.set_override("time.dt=0.25");
  document.set_override("output.dir=/tmp/x");
  auto root = document.root();
  EXPECT_DOUBLE_EQ(root.section("time").get<double>("dt", 0.0, positive()), 0.25);
  EXPECT_EQ(root.section("output").get<std::string>("dir", ""), "/tmp/x");
  document.set_override("time.dt=-1");
  EXPECT_EQ(test::input_error_message(
                [&] { document.root().section("time").get<double>("dt", 0.0, positive()); }),
            "time.dt: expected a positive number, got -1");
  EXPECT_NE(test::input_error_message([&] { document.set_override("novalue"); }),
            "no InputError thrown");
}

TEST(Config, EmitRoundTripsAndHashIgnoresOutputCheckpointAndSolverOptions) {
  auto a = ConfigDocument::parse("x: 1\noutput: {dir: a}", "a.yaml");
  auto b = ConfigDocument::parse("x: 1\noutput: {dir: b}\ncheckpoint: {every: 5}\n"
                                 "petsc: {ksp_rtol: 1e-12}",
                                 "b.yaml");
  auto c = ConfigDocument::parse("x: 2\noutput: {dir: a}", "c.yaml");
  EXPECT_EQ(a.result_hash(), b.result_hash());
  EXPECT_NE(a.result_hash(), c.result_hash());
  auto again = ConfigDocument::parse(a.emit(), "again.yaml");
  EXPECT_EQ(again.result_hash(), a.result_hash());
}

TEST(Config, RunLengthKeysAreLeftOutOfTheHash) {
  auto short_run = ConfigDocument::parse("p: {time: {steps: 10, dt: 0.5}}", "a.yaml");
  auto long_run = ConfigDocument::parse("p: {time: {steps: 90, dt: 0.5}}", "b.yaml");
  auto other_dt = ConfigDocument::parse("p: {time: {steps: 90, dt: 0.25}}", "c.yaml");
  const std::vector<std::string> keys = {"p.time.steps"};
  EXPECT_NE(short_run.result_hash(), long_run.result_hash());
  EXPECT_EQ(short_run.result_hash(keys), long_run.result_hash(keys));
  EXPECT_NE(long_run.result_hash(keys), other_dt.result_hash(keys));
}

TEST(Config, FreeFormMapsAreNotCheckedForUnknownKeys) {
  auto document = ConfigDocument::parse("petsc: {ksp_type: cg, ksp_rtol: 1e-9}", "t.yaml");
  const auto petsc = document.root().string_map("petsc");
  EXPECT_EQ(petsc.at("ksp_type"), "cg");
  EXPECT_EQ(petsc.at("ksp_rtol"), "1e-9");
  EXPECT_NO_THROW(document.check_unknown_keys());
}

TEST(Config, BadYamlAndMissingFileNameTheSource) {
  EXPECT_NE(test::input_error_message([] {
              ConfigDocument::parse("a: [1, 2", "broken.yaml");
            }).find("broken.yaml: not valid YAML"),
            std::string::npos);
  EXPECT_NE(test::input_error_message([] {
              ConfigDocument::load("/nonexistent/x.yaml");
            }).find("/nonexistent/x.yaml: no such file"),
            std::string::npos);
}

TEST(Config, EditDistance) {
  EXPECT_EQ(edit_distance("kitten", "sitting"), 3u);
  EXPECT_EQ(edit_distance("", "abc"), 3u);
  EXPECT_EQ(edit_distance("same", "same"), 0u);
}

} // namespace
} // namespace texsim
