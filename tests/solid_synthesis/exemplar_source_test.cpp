#include "pipelines/solid_synthesis/exemplar_source.hpp"

#include "support/input_error.hpp"
#include "support/test_data.hpp"
#include "vol/procedural_exemplars.hpp"
#include "vol/vdb_io.hpp"
#include "vol/vti_io.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <fstream>
#include <string>

namespace texsim::pipelines::solid_synthesis {
namespace {

using test::input_error_message;

/// Settings from the `exemplar:` entries given as YAML flow-map contents; the section must read
/// cleanly (no unknown keys).
ExemplarSettings settings_from(const std::string& entries) {
  auto document =
      ConfigDocument::parse("solid_synthesis:\n  exemplar: {" + entries + "}\n", "test.yaml");
  const ExemplarSettings settings =
      read_exemplar_settings(document.root().section("solid_synthesis").section("exemplar"));
  document.check_unknown_keys();
  return settings;
}

/// The InputError message reading the entries gives.
std::string error_from(const std::string& entries) {
  return input_error_message([&] { settings_from(entries); });
}

bool contains(const std::string& text, const std::string& part) {
  return text.find(part) != std::string::npos;
}

TEST(ExemplarSource, DefaultsAreAToroidalMarbleOf64Voxels) {
  const ExemplarSettings s = settings_from("");
  EXPECT_FALSE(s.file);
  EXPECT_EQ(s.procedural, ProceduralExemplar::marble);
  EXPECT_EQ(s.size, 64);
  EXPECT_EQ(s.seed, 1u);
  EXPECT_EQ(s.border, ExemplarBorder::toroidal);
  EXPECT_EQ(s.key_path, "solid_synthesis.exemplar");
}

TEST(ExemplarSource, ReadsEveryGeneratorAndItsKeys) {
  const std::pair<const char*, ProceduralExemplar> names[] = {
      {"marble", ProceduralExemplar::marble},   {"particles", ProceduralExemplar::particles},
      {"wood", ProceduralExemplar::wood},       {"bricks", ProceduralExemplar::bricks},
      {"noise", ProceduralExemplar::noise},     {"strokes", ProceduralExemplar::strokes},
      {"stripes", ProceduralExemplar::stripes}, {"lattice", ProceduralExemplar::lattice}};
  for (const auto& [name, value] : names) {
    const ExemplarSettings s =
        settings_from(std::string("procedural: ") + name + ", size: 16, seed: 9, border: discard");
    EXPECT_EQ(s.procedural, value) << name;
    EXPECT_EQ(s.size, 16) << name;
    EXPECT_EQ(s.seed, 9u) << name;
    EXPECT_EQ(s.border, ExemplarBorder::discard) << name;
    const Exemplar e = load_exemplar(s);
    EXPECT_EQ(e.colours.dims(), (vol::Dims{16, 16, 16})) << name;
    EXPECT_EQ(e.colours.channels(), 3) << name;
    EXPECT_FALSE(e.scalar) << name;
    EXPECT_TRUE(contains(e.description, name)) << e.description;
  }
  const ExemplarSettings lattice = settings_from("procedural: lattice, size: 24, period: 6");
  EXPECT_EQ(lattice.period, 6);
  const Exemplar e = load_exemplar(lattice);
  EXPECT_TRUE(e.colours == vol::to_channels(vol::lattice_exemplar(24, 6, 1)));
}

TEST(ExemplarSource, BadEntriesNameTheirKeyPath) {
  EXPECT_TRUE(contains(error_from("procedural: granite"), "solid_synthesis.exemplar.procedural"));
  EXPECT_TRUE(contains(error_from("procedural: granite"), "lattice")); // lists the choices
  EXPECT_TRUE(contains(error_from("size: 4"), "solid_synthesis.exemplar.size"));
  EXPECT_TRUE(contains(error_from("size: -64"), "solid_synthesis.exemplar.size"));
  EXPECT_TRUE(contains(error_from("size: big"), "solid_synthesis.exemplar.size"));
  const std::string not_multiple = error_from("procedural: lattice, size: 60, period: 8");
  EXPECT_TRUE(contains(not_multiple, "solid_synthesis.exemplar.size"));
  EXPECT_TRUE(contains(not_multiple, "solid_synthesis.exemplar.period"));
  EXPECT_TRUE(
      contains(error_from("procedural: marble, period: 8"), "solid_synthesis.exemplar.period"));
  EXPECT_TRUE(contains(error_from("border: mirrored"), "solid_synthesis.exemplar.border"));
  EXPECT_TRUE(
      contains(error_from("file: /nonexistent/granite.vti"), "solid_synthesis.exemplar.file"));
}

TEST(ExemplarSource, AFileExcludesTheProceduralKeys) {
  const auto dir = test::scratch_dir("exemplar_source_keys");
  const auto path = dir / "marble.vti";
  vol::write_vti(path, vol::marble_exemplar(8, 1), "colour");
  const std::string file = "file: " + path.string();
  EXPECT_TRUE(
      contains(error_from(file + ", procedural: marble"), "solid_synthesis.exemplar.procedural"));
  EXPECT_TRUE(contains(error_from(file + ", size: 32"), "solid_synthesis.exemplar.size"));
  EXPECT_TRUE(contains(error_from(file + ", seed: 2"), "solid_synthesis.exemplar.seed"));
  const auto text = dir / "notes.txt";
  std::ofstream(text) << "not a volume\n";
  EXPECT_TRUE(contains(error_from("file: " + text.string()), "solid_synthesis.exemplar.file"));
}

TEST(ExemplarSource, ColourVtiRoundTripsExactly) {
  const auto dir = test::scratch_dir("exemplar_source_vti");
  const vol::RgbGrid written = vol::wood_exemplar(12, 4);
  const auto path = dir / "wood.vti";
  vol::write_vti(path, written, "colour");
  const ExemplarSettings settings = settings_from("file: " + path.string() + ", border: discard");
  EXPECT_EQ(*settings.file, path);
  const Exemplar e = load_exemplar(settings);
  EXPECT_FALSE(e.scalar);
  EXPECT_TRUE(e.colours == vol::to_channels(written));
  EXPECT_TRUE(contains(e.description, path.string()));
  // The hash depends on the values only: the procedural twin of the file has the same one.
  const Exemplar twin = load_exemplar(settings_from("procedural: wood, size: 12, seed: 4"));
  EXPECT_EQ(e.content_hash, twin.content_hash);
  EXPECT_EQ(e.content_hash.size(), 16u);
  EXPECT_NE(e.content_hash,
            load_exemplar(settings_from("procedural: wood, size: 12, seed: 5")).content_hash);
}

TEST(ExemplarSource, ScalarVdbStaysOneChannelRescaledToTheUnitRange) {
  const auto dir = test::scratch_dir("exemplar_source_vdb");
  vol::ScalarGrid density(vol::Dims{10, 9, 8});
  for (int k = 0; k < 8; ++k) {
    for (int j = 0; j < 9; ++j) {
      for (int i = 0; i < 10; ++i) {
        density.at(i, j, k) = 2.0f + 0.25f * static_cast<float>(i + j + k); // [2, 8]
      }
    }
  }
  const auto path = dir / "density.vdb";
  vol::write_vdb(path, density, "density");
  const Exemplar e = load_exemplar(settings_from("file: " + path.string()));
  EXPECT_TRUE(e.scalar);
  ASSERT_EQ(e.colours.channels(), 1);
  ASSERT_EQ(e.colours.dims(), density.dims());
  for (int k = 0; k < 8; ++k) {
    for (int j = 0; j < 9; ++j) {
      for (int i = 0; i < 10; ++i) {
        const float expected = (density.at(i, j, k) - 2.0f) / 6.0f;
        ASSERT_NEAR(e.colours.voxel(e.colours.index(i, j, k))[0], expected, 1e-6f);
      }
    }
  }
}

TEST(ExemplarSource, UnreadableFilesNameTheKeyAndTheFile) {
  const auto dir = test::scratch_dir("exemplar_source_broken");
  const auto path = dir / "broken.vti";
  std::ofstream(path) << "<VTKFile type=\"ImageData\"> truncated";
  const ExemplarSettings settings = settings_from("file: " + path.string());
  const std::string message = input_error_message([&] { load_exemplar(settings); });
  EXPECT_TRUE(contains(message, "solid_synthesis.exemplar.file")) << message;
  EXPECT_TRUE(contains(message, "broken.vti")) << message;
}

TEST(ExemplarSource, ExemplarsSmallerThanTwoWindowsAreRefused) {
  const ExemplarSettings settings = settings_from("procedural: noise, size: 9");
  const Exemplar e = load_exemplar(settings);
  const std::string message =
      input_error_message([&] { require_exemplar_fits_window(e, settings, 5); });
  EXPECT_TRUE(contains(message, "solid_synthesis.exemplar")) << message;
  EXPECT_TRUE(contains(message, "10")) << message;
  EXPECT_EQ(input_error_message([&] { require_exemplar_fits_window(e, settings, 3); }),
            "no InputError thrown");
}

} // namespace
} // namespace texsim::pipelines::solid_synthesis
