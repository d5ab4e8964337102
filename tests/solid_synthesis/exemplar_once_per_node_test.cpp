#include "pipelines/solid_synthesis/exemplar_source.hpp"

#include "core/config.hpp"
#include "par/comm.hpp"
#include "support/input_error.hpp"
#include "support/test_data.hpp"
#include "vol/vdb_io.hpp"

#include <gtest/gtest.h>

#include <mpi.h>

#include <fstream>
#include <string>

namespace texsim::pipelines::solid_synthesis {
namespace {

ExemplarSettings settings_from(const std::string& entries) {
  auto document =
      ConfigDocument::parse("solid_synthesis:\n  exemplar: {" + entries + "}\n", "test.yaml");
  return read_exemplar_settings(document.root().section("solid_synthesis").section("exemplar"));
}

/// The exemplar loaded on rank 0 and held once per node equals what a serial load gives, on
/// every rank: values, kind, description and hash.
void expect_same_as_serial_load(const ExemplarSettings& settings) {
  const Exemplar shared = load_exemplar_once_per_node(par::world(), settings);
  const Exemplar serial = load_exemplar(settings);
  EXPECT_TRUE(shared.colours.node_shared());
  EXPECT_TRUE(shared.colours == serial.colours);
  EXPECT_EQ(shared.scalar, serial.scalar);
  EXPECT_EQ(shared.description, serial.description);
  EXPECT_EQ(shared.content_hash, serial.content_hash);
}

TEST(ExemplarOncePerNode, ProceduralExemplarsEqualTheSerialLoad) {
  expect_same_as_serial_load(settings_from("procedural: marble, size: 16, seed: 3"));
  expect_same_as_serial_load(settings_from("procedural: lattice, size: 12, period: 4"));
}

TEST(ExemplarOncePerNode, AScalarFileStaysOneChannel) {
  const auto dir = test::scratch_dir("exemplar_once_per_node_vdb");
  const auto path = dir / "density.vdb";
  if (par::world().is_root()) {
    vol::ScalarGrid density(vol::Dims{10, 9, 8});
    for (int k = 0; k < 8; ++k)
      for (int j = 0; j < 9; ++j)
        for (int i = 0; i < 10; ++i)
          density.at(i, j, k) = 1.0f + 0.5f * static_cast<float>(i * j - k);
    vol::write_vdb(path, density, "density");
  }
  MPI_Barrier(par::world().raw);
  const ExemplarSettings settings = settings_from("file: " + path.string());
  expect_same_as_serial_load(settings);
  EXPECT_TRUE(load_exemplar_once_per_node(par::world(), settings).scalar);
}

TEST(ExemplarOncePerNode, ABrokenFileFailsEveryRankWithTheKeyAndTheFile) {
  const auto dir = test::scratch_dir("exemplar_once_per_node_broken");
  const auto path = dir / "broken.vti";
  if (par::world().is_root())
    std::ofstream(path) << "<VTKFile type=\"ImageData\"> truncated";
  MPI_Barrier(par::world().raw);
  const ExemplarSettings settings = settings_from("file: " + path.string());
  const std::string message =
      test::input_error_message([&] { load_exemplar_once_per_node(par::world(), settings); });
  EXPECT_NE(message.find("solid_synthesis.exemplar.file"), std::string::npos) << message;
  EXPECT_NE(message.find("broken.vti"), std::string::npos) << message;
}

} // namespace
} // namespace texsim::pipelines::solid_synthesis
