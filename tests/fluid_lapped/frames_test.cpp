// Simulator frames: a numbered series of OpenVDB level sets (a sphere whose radius grows) is
// meshed at its zero crossing, repaired and remeshed into a closed, outward-oriented surface of
// the sphere's area; velocity grids read from .vdb equal those read from .vti; a frame series
// whose velocity grids are at other times, or of another format, is refused.
#include "core/error.hpp"
#include "geom/mesh_measures.hpp"
#include "geom/mesh_topology.hpp"
#include "pipelines/fluid_lapped/fluid_frames.hpp"
#include "vol/vdb_io.hpp"
#include "vol/vti_io.hpp"

#include <Eigen/Geometry>
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>

namespace texsim::pipelines::fluid_lapped {
namespace {
namespace fs = std::filesystem;

/// The signed distance to a sphere of `radius` on a 41^3 grid over [-1.2, 1.2]^3.
vol::ScalarGrid sphere_level_set(double radius) {
  vol::ScalarGrid grid(vol::Dims{41, 41, 41});
  grid.set_spacing({0.06, 0.06, 0.06});
  grid.set_origin({-1.2, -1.2, -1.2});
  for (int k = 0; k < 41; ++k)
    for (int j = 0; j < 41; ++j)
      for (int i = 0; i < 41; ++i)
        grid.at(i, j, k) = float(
            Eigen::Vector3d(-1.2 + 0.06 * i, -1.2 + 0.06 * j, -1.2 + 0.06 * k).norm() - radius);
  return grid;
}

fs::path scratch() {
  const auto dir = fs::temp_directory_path() / "texsim_fluid_frames_test";
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

TEST(FluidFrames, LevelSetSeriesGivesClosedOutwardSurfaces) {
  const auto dir = scratch();
  for (int k = 0; k < 2; ++k)
    vol::write_vdb(dir / ("sphere_" + std::to_string(k) + ".vdb"), sphere_level_set(0.8 + 0.05 * k),
                   "surface");
  FrameSourceSettings settings;
  settings.frames = (dir / "sphere_%d.vdb").string();
  settings.frame_interval = 0.5;
  settings.velocity_array.clear();
  settings.edge_length = 0.08;
  const FrameSource source(settings);
  ASSERT_EQ(source.frame_count(), 2);
  EXPECT_EQ(source.time(1), 0.5);
  for (int k = 0; k < 2; ++k) {
    const auto frame = source.read(k);
    const geom::MeshTopology topology(frame.mesh);
    EXPECT_TRUE(topology.is_closed());
    EXPECT_TRUE(topology.is_manifold());
    const double r = 0.8 + 0.05 * k;
    EXPECT_NEAR(geom::total_area(frame.mesh), 4 * M_PI * r * r, 0.02 * 4 * M_PI * r * r);
    double volume = 0; // positive when the triangles face outwards
    for (const auto& t : frame.mesh.triangles)
      volume +=
          frame.mesh.positions[std::size_t(t[0])].dot(frame.mesh.positions[std::size_t(t[1])].cross(
              frame.mesh.positions[std::size_t(t[2])])) /
          6.0;
    EXPECT_NEAR(volume, 4.0 / 3.0 * M_PI * r * r * r, 0.03 * 4.0 / 3.0 * M_PI * r * r * r);
    EXPECT_NEAR(geom::mean_edge_length(frame.mesh), 0.08, 0.02);
  }
}

TEST(FluidFrames, VelocityGridsAtOtherTimesAreRefused) {
  const auto dir = scratch();
  vol::RgbGrid velocity(vol::Dims{2, 2, 2});
  for (int k = 0; k < 2; ++k) {
    vol::write_vdb(dir / ("sphere_" + std::to_string(k) + ".vdb"), sphere_level_set(0.8),
                   "surface");
    vol::write_vti(dir / ("u_" + std::to_string(k) + ".vti"), velocity, "U");
  }
  vol::write_vti(dir / "u_2.vti", velocity, "U"); // one grid too many
  FrameSourceSettings settings;
  settings.frames = (dir / "sphere_%d.vdb").string();
  settings.velocity_array.clear();
  settings.velocity_grids = (dir / "u_%d.vti").string();
  try {
    const FrameSource source(settings);
    FAIL() << "accepted 3 velocity grids for 2 frames";
  } catch (const InputError& error) {
    EXPECT_NE(std::string(error.what()).find("fluid_lapped.frames.velocity_grids"),
              std::string::npos)
        << error.what();
  }
}

/// A swirl about the z axis plus an upward drift, on a 9^3 grid over [-1.2, 1.2]^3.
vol::RgbGrid swirl_velocity(float drift) {
  vol::RgbGrid grid(vol::Dims{9, 9, 9});
  grid.set_spacing({0.3, 0.3, 0.3});
  grid.set_origin({-1.2, -1.2, -1.2});
  for (int k = 0; k < 9; ++k)
    for (int j = 0; j < 9; ++j)
      for (int i = 0; i < 9; ++i)
        grid.at(i, j, k) = {-(-1.2f + 0.3f * float(j)), -1.2f + 0.3f * float(i), drift};
  return grid;
}

TEST(FluidFrames, VdbVelocityGridsGiveTheVtiVelocity) {
  const auto dir = scratch();
  for (int k = 0; k < 2; ++k) {
    const auto name = std::to_string(k);
    vol::write_vdb(dir / ("sphere_" + name + ".vdb"), sphere_level_set(0.8), "surface");
    vol::write_vti(dir / ("u_" + name + ".vti"), swirl_velocity(0.1f * float(k + 1)), "U");
    vol::write_vdb(dir / ("u_" + name + ".vdb"), swirl_velocity(0.1f * float(k + 1)), "vel");
  }
  FrameSourceSettings settings;
  settings.frames = (dir / "sphere_%d.vdb").string();
  settings.velocity_array.clear();
  settings.velocity_grids = (dir / "u_%d.vti").string();
  const FrameSource from_vti(settings);
  settings.velocity_grids = (dir / "u_%d.vdb").string(); // grid name: "vel" by default
  const FrameSource from_vdb(settings);
  ASSERT_TRUE(from_vdb.has_velocity_grids());
  const auto vti =
      make_grid_velocity(from_vti.velocity_grid(0), 0.0, from_vti.velocity_grid(1), 1.0);
  const auto vdb =
      make_grid_velocity(from_vdb.velocity_grid(0), 0.0, from_vdb.velocity_grid(1), 1.0);
  for (const geom::Vec3& x : {geom::Vec3(0.31, -0.52, 0.17), geom::Vec3(-0.9, 0.05, 0.77)})
    for (const double t : {0.0, 0.25, 1.0}) {
      const auto expected = vti->at(x, t);
      EXPECT_EQ(vdb->at(x, t), expected) << "at t = " << t;
      EXPECT_NEAR(expected.z(), 0.1 + 0.1 * t, 1e-6); // linear in time between the two grids
      EXPECT_NEAR(expected.x(), -x.y(), 1e-6);        // trilinear reproduces a linear field
    }
}

TEST(FluidFrames, VelocityGridOfAnotherFormatIsRefused) {
  const auto dir = scratch();
  vol::write_vdb(dir / "sphere_0.vdb", sphere_level_set(0.8), "surface");
  std::ofstream(dir / "u_0.h5") << "not a grid";
  FrameSourceSettings settings;
  settings.frames = (dir / "sphere_%d.vdb").string();
  settings.velocity_array.clear();
  settings.velocity_grids = (dir / "u_%d.h5").string();
  try {
    const FrameSource source(settings);
    FAIL() << "accepted an .h5 velocity grid";
  } catch (const InputError& error) {
    EXPECT_NE(std::string(error.what()).find("neither a .vti nor a .vdb"), std::string::npos)
        << error.what();
  }
}

} // namespace
} // namespace texsim::pipelines::fluid_lapped
