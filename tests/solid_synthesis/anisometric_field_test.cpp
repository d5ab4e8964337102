#include "pipelines/solid_synthesis/anisometric_field.hpp"
#include "pipelines/solid_synthesis/anisometric_field_settings.hpp"

#include "support/input_error.hpp"
#include "support/test_data.hpp"
#include "vol/hdf5_grid_io.hpp"
#include "vol/vdb_io.hpp"
#include "vol/vti_io.hpp"

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <fstream>
#include <numbers>
#include <string>

namespace texsim::pipelines::solid_synthesis {
namespace {

using test::input_error_message;

constexpr double kPi = std::numbers::pi;

/// The field a config section describes (the section must read cleanly).
std::unique_ptr<AxesField> field_from_yaml(const std::string& yaml) {
  auto document = ConfigDocument::parse(yaml, "field.yaml");
  const FieldSettings settings = read_field_settings(document.root().section("field"));
  document.check_unknown_keys();
  return make_axes_field(settings);
}

/// Deterministic points spread over the unit cube (a 3D Halton-like lattice).
std::vector<Eigen::Vector3d> sample_points(int count) {
  std::vector<Eigen::Vector3d> points;
  for (int s = 0; s < count; ++s) {
    points.emplace_back(std::fmod(0.1 + 0.618034 * s, 1.0), std::fmod(0.2 + 0.754878 * s, 1.0),
                        std::fmod(0.3 + 0.569840 * s, 1.0));
  }
  return points;
}

Eigen::Matrix3d rotation_z_degrees(double degrees) {
  return Eigen::AngleAxisd(degrees * kPi / 180.0, Eigen::Vector3d::UnitZ()).toRotationMatrix();
}

double max_difference(const Eigen::Matrix3f& a, const Eigen::Matrix3f& b) {
  return (a - b).cwiseAbs().maxCoeff();
}

TEST(AnisometricField, IdentityGivesIdentityMatrices) {
  const auto field = field_from_yaml("field: {type: identity}");
  const LevelJacobians level = sample_level(*field, 4, 0, 4, 16);
  ASSERT_EQ(level.jacobian.size(), 64u);
  for (int k = 0; k < 4; ++k) {
    for (int j = 0; j < 4; ++j) {
      for (int i = 0; i < 4; ++i) {
        EXPECT_EQ(level.a(i, j, k), Eigen::Matrix3f::Identity());
        EXPECT_EQ(level.a_inverse(i, j, k), Eigen::Matrix3f::Identity());
      }
    }
  }
}

TEST(AnisometricField, SlantIsTheRotationAboutZ) {
  const auto field = field_from_yaml("field: {type: slant, angle_degrees: 30}");
  const Eigen::Matrix3d f = field->axes({0.3, 0.7, 0.1});
  EXPECT_NEAR((f - rotation_z_degrees(30)).norm(), 0.0, 1e-12);
  EXPECT_NEAR(f(0, 0), std::sqrt(3.0) / 2.0, 1e-12); // exemplar x axis turned by +30 degrees
  EXPECT_NEAR(f(1, 0), 0.5, 1e-12);
  EXPECT_NEAR(f.determinant(), 1.0, 1e-12);

  const LevelJacobians level = sample_level(*field, 8, 2, 5, 8);
  for (int k = 2; k < 5; ++k) {
    const Eigen::Matrix3f product = level.a(3, 6, k) * level.a_inverse(3, 6, k);
    EXPECT_LT(max_difference(product, Eigen::Matrix3f::Identity()), 1e-6f);
    EXPECT_LT(max_difference(level.a(3, 6, k), rotation_z_degrees(-30).cast<float>()), 1e-6f);
  }
}

TEST(AnisometricField, Slant3dBy120DegreesCyclesTheAxes) {
  // A third of a turn about (1, 1, 1) sends x to y, y to z and z to x.
  const auto field = field_from_yaml("field: {type: slant3d, angle_degrees: 120}");
  Eigen::Matrix3d cycle;
  cycle << 0, 0, 1, 1, 0, 0, 0, 1, 0;
  EXPECT_NEAR((field->axes({0.5, 0.5, 0.5}) - cycle).norm(), 0.0, 1e-12);
}

TEST(AnisometricField, CircularAxesAreTangentAndInwardRadial) {
  const auto field = field_from_yaml("field: {type: circular}");
  for (const Eigen::Vector3d& p : sample_points(50)) {
    const Eigen::Matrix3d f = field->axes(p);
    const Eigen::Vector3d radial = Eigen::Vector3d(p.x() - 0.5, p.y() - 0.5, 0.0).normalized();
    EXPECT_NEAR(f.col(0).dot(radial), 0.0, 1e-12);       // tangent to the circle
    EXPECT_NEAR(radial.cross(f.col(0)).z(), 1.0, 1e-12); // counter-clockwise, unit
    EXPECT_NEAR((f.col(1) + radial).norm(), 0.0, 1e-12); // y axis points inwards
    EXPECT_NEAR((f.col(2) - Eigen::Vector3d::UnitZ()).norm(), 0.0, 1e-12);
  }
}

TEST(AnisometricField, OvalAxesAreTangentToEllipsesOfTheRatio) {
  const auto field = field_from_yaml("field: {type: oval, ratio: 3}");
  for (const Eigen::Vector3d& p : sample_points(50)) {
    const Eigen::Matrix3d f = field->axes(p);
    // Normal of the level sets of (dx / 3)^2 + dy^2.
    const Eigen::Vector3d normal((p.x() - 0.5) / 9.0, p.y() - 0.5, 0.0);
    EXPECT_NEAR(f.col(0).dot(normal.normalized()), 0.0, 1e-12);
    EXPECT_NEAR(f.determinant(), 1.0, 1e-12);
  }
  const auto circle = field_from_yaml("field: {type: circular}");
  const auto ratio_one = field_from_yaml("field: {type: oval, ratio: 1}");
  EXPECT_EQ(circle->axes({0.2, 0.9, 0.4}), ratio_one->axes({0.2, 0.9, 0.4}));
}

TEST(AnisometricField, ZigzagAlternatesSmoothlyBetweenTheTwoSlants) {
  const auto field = field_from_yaml("field: {type: zigzag, angle_degrees: 30, bands: 4}");
  for (int band = 0; band < 4; ++band) {
    const double centre = (band + 0.5) / 4.0;
    const double expected = band % 2 == 0 ? 30.0 : -30.0;
    EXPECT_NEAR((field->axes({0.3, centre, 0.6}) - rotation_z_degrees(expected)).norm(), 0.0, 1e-12)
        << "band " << band;
  }
  // No jumps: the angle changes by a bounded amount between neighbouring points along y.
  double largest_step = 0.0;
  double previous = 0.0;
  for (int s = 0; s <= 1000; ++s) {
    const Eigen::Matrix3d f = field->axes({0.5, s / 1000.0, 0.5});
    const double angle = std::atan2(f(1, 0), f(0, 0)) * 180.0 / kPi;
    if (s > 0) {
      largest_step = std::max(largest_step, std::abs(angle - previous));
    }
    previous = angle;
  }
  EXPECT_LT(largest_step, 2.0);
}

TEST(AnisometricField, CoarseLevelOfAConstantFieldEqualsTheFineOne) {
  const auto field = field_from_yaml("field: {type: slant3d, angle_degrees: 40}");
  const LevelJacobians fine = sample_level(*field, 16, 0, 16, 16);
  const LevelJacobians coarse = sample_level(*field, 4, 0, 4, 16);
  for (int k = 0; k < 4; ++k) {
    for (int j = 0; j < 4; ++j) {
      for (int i = 0; i < 4; ++i) {
        EXPECT_LT(max_difference(coarse.a(i, j, k), fine.a(4 * i, 4 * j, 4 * k)), 1e-6f);
        EXPECT_LT(max_difference(coarse.a_inverse(i, j, k), fine.a_inverse(4 * i, 4 * j, 4 * k)),
                  1e-6f);
      }
    }
  }
}

TEST(AnisometricField, CoarseInverseIsTheMeanOfItsFinestChildren) {
  // One level above the finest, the stratified sample is exactly the 8 children's centres.
  const auto field = field_from_yaml("field: {type: oval, ratio: 2}");
  const LevelJacobians fine = sample_level(*field, 16, 0, 16, 16);
  const LevelJacobians coarse = sample_level(*field, 8, 0, 8, 16);
  for (int k = 0; k < 8; k += 3) {
    for (int j = 0; j < 8; ++j) {
      for (int i = 0; i < 8; ++i) {
        Eigen::Matrix3f mean = Eigen::Matrix3f::Zero();
        for (int child = 0; child < 8; ++child) {
          mean += fine.a_inverse(2 * i + (child & 1), 2 * j + ((child >> 1) & 1),
                                 2 * k + (child >> 2)) /
                  8.0f;
        }
        if (std::abs(mean.determinant()) < kSingularFrameDeterminant) {
          continue;
        }
        EXPECT_LT(max_difference(coarse.a_inverse(i, j, k), mean), 1e-6f);
        EXPECT_LT(max_difference(coarse.a(i, j, k) * mean, Eigen::Matrix3f::Identity()), 1e-5f);
      }
    }
  }
}

TEST(AnisometricField, SingularAverageAtTheCircleCentreFallsBackToIdentity) {
  const auto field = field_from_yaml("field: {type: circular}");
  const LevelJacobians whole = sample_level(*field, 1, 0, 1, 16);
  EXPECT_EQ(whole.a(0, 0, 0), Eigen::Matrix3f::Identity());
  EXPECT_EQ(whole.a_inverse(0, 0, 0), Eigen::Matrix3f::Identity());
  // One level finer, each quadrant averages to a regular (shortened) frame.
  const LevelJacobians quadrants = sample_level(*field, 2, 0, 2, 16);
  EXPECT_GT(std::abs(quadrants.a_inverse(0, 0, 0).determinant()), 0.5f);
  EXPECT_NE(quadrants.a_inverse(0, 0, 0), Eigen::Matrix3f::Identity());
}

TEST(AnisometricField, PlanesOutsideTheLevelWrapAround) {
  const auto field = field_from_yaml("field: {type: oval, ratio: 2}");
  const LevelJacobians all = sample_level(*field, 8, 0, 8, 32);
  const LevelJacobians halo = sample_level(*field, 8, -2, 10, 32);
  for (int k = -2; k < 10; ++k) {
    EXPECT_EQ(halo.a(5, 1, k), all.a(5, 1, (k + 8) % 8)) << "plane " << k;
    EXPECT_EQ(halo.a_inverse(2, 7, k), all.a_inverse(2, 7, (k + 8) % 8)) << "plane " << k;
  }
}

TEST(AnisometricField, FrameFromXAxisIsRightHandedWithUnitYAndZ) {
  const Eigen::Vector3d vectors[] = {
      {2.0, 0.0, 0.0}, {0.3, -0.4, 1.2}, {0.0, 0.0, -0.5}, {0.0, 0.0, 3.0}, {-1.0, 2.0, 0.0}};
  for (const Eigen::Vector3d& v : vectors) {
    const Eigen::Matrix3d f = frame_from_x_axis(v);
    EXPECT_EQ(f.col(0), v);
    EXPECT_NEAR(f.col(1).norm(), 1.0, 1e-12);
    EXPECT_NEAR(f.col(2).norm(), 1.0, 1e-12);
    EXPECT_NEAR(f.col(0).dot(f.col(1)), 0.0, 1e-12);
    EXPECT_NEAR(f.col(0).dot(f.col(2)), 0.0, 1e-12);
    EXPECT_NEAR(f.col(1).dot(f.col(2)), 0.0, 1e-12);
    EXPECT_NEAR(f.determinant(), v.norm(), 1e-12);
    if (v.head<2>().norm() > 0.0) { // z axis in the plane of v and z (Gram-Schmidt against z)
      EXPECT_NEAR(f.col(2).dot(v.cross(Eigen::Vector3d::UnitZ())), 0.0, 1e-12);
      EXPECT_GT(f.col(2).z(), 0.0);
    }
  }
  EXPECT_EQ(frame_from_x_axis(Eigen::Vector3d::Zero()), Eigen::Matrix3d::Identity());
}

/// The exemplar x axis of the analytic test field: a swirl in XY whose length grows with y.
Eigen::Vector3d swirl(const Eigen::Vector3d& p) {
  const double angle = 2.0 * kPi * (p.x() + 0.5 * p.z());
  return (1.0 + 0.5 * p.y()) * Eigen::Vector3d(std::cos(angle), std::sin(angle), 0.0);
}

vol::RgbGrid sampled_swirl(int n) {
  vol::RgbGrid grid({n, n, n});
  for (int k = 0; k < n; ++k) {
    for (int j = 0; j < n; ++j) {
      for (int i = 0; i < n; ++i) {
        const Eigen::Vector3d v = swirl(Eigen::Vector3d(i + 0.5, j + 0.5, k + 0.5) / n);
        grid.at(i, j, k) = {static_cast<float>(v.x()), static_cast<float>(v.y()),
                            static_cast<float>(v.z())};
      }
    }
  }
  return grid;
}

TEST(AnisometricField, FileFieldRoundTripMatchesTheAnalyticField) {
  constexpr int n = 32;
  const auto dir = test::scratch_dir("anisometric_file_field");
  const vol::RgbGrid grid = sampled_swirl(n);
  vol::write_vti(dir / "swirl.vti", grid, "axis");
  vol::write_vdb(dir / "swirl.vdb", grid, "axis");
  vol::write_hdf5_grid(dir / "swirl.h5", grid, "axis");
  const auto from_vti =
      field_from_yaml("field: {type: file, file: " + (dir / "swirl.vti").string() + "}");
  const auto from_vdb =
      field_from_yaml("field: {type: file, file: " + (dir / "swirl.vdb").string() + "}");
  const auto from_h5 =
      field_from_yaml("field: {type: file, file: " + (dir / "swirl.h5").string() + "}");

  // At voxel centres the interpolation is exact (to float rounding).
  for (const auto& [i, j, k] :
       {std::array{0, 0, 0}, std::array{5, 17, 30}, std::array{31, 31, 9}}) {
    const Eigen::Vector3d p = Eigen::Vector3d(i + 0.5, j + 0.5, k + 0.5) / n;
    EXPECT_NEAR((from_vti->axes(p).col(0) - swirl(p)).norm(), 0.0, 1e-6);
  }
  // Elsewhere (inside the outermost voxel centres) within the trilinear interpolation error
  // h^2 / 8 (|v_xx| + |v_zz|) <= (1/32)^2 / 8 * (2 pi)^2 * 1.25 * 1.5 = 0.009 (measured 0.0082).
  double worst = 0.0;
  for (const Eigen::Vector3d& s : sample_points(200)) {
    const Eigen::Vector3d p = Eigen::Vector3d::Constant(0.5 / n) + s * (1.0 - 1.0 / n);
    const Eigen::Vector3d v = swirl(p);
    const Eigen::Matrix3d expected =
        (Eigen::Matrix3d() << v, Eigen::Vector3d(-v.y(), v.x(), 0.0).normalized(),
         Eigen::Vector3d::UnitZ())
            .finished();
    const Eigen::Matrix3d f = from_vti->axes(p);
    worst = std::max(worst, (f - expected).cwiseAbs().maxCoeff());
    EXPECT_EQ(f, from_vdb->axes(p));
    EXPECT_EQ(f, from_h5->axes(p));
  }
  EXPECT_LT(worst, 0.012);
  EXPECT_GT(worst, 1e-5); // the sample points are not all at voxel centres

  // Levels sampled from the file field are regular frames: A A^-1 = I.
  const LevelJacobians level = sample_level(*from_vti, 8, 0, 8, 32);
  for (std::size_t v = 0; v < level.jacobian.size(); v += 37) {
    EXPECT_LT(max_difference(level.jacobian[v] * level.inverse[v], Eigen::Matrix3f::Identity()),
              1e-5f);
  }
}

TEST(AnisometricField, ConfigErrorsNameTheKeyPath) {
  const auto read = [](const std::string& yaml) {
    auto document = ConfigDocument::parse(yaml, "run.yaml");
    const FieldSettings settings = read_field_settings(document.root().section("field"));
    document.check_unknown_keys();
    return make_axes_field(settings);
  };
  EXPECT_NE(input_error_message([&] { read("field: {type: spiral}"); })
                .find("field.type: expected one of identity, circular, oval, slant, zigzag, "
                      "slant3d, file, got spiral"),
            std::string::npos);
  EXPECT_NE(input_error_message([&] {
              read("field: {type: zigzag, bands: 0}");
            }).find("field.bands: expected"),
            std::string::npos);
  EXPECT_NE(input_error_message([&] {
              read("field: {type: oval, ratio: -2}");
            }).find("field.ratio: expected a positive number"),
            std::string::npos);
  EXPECT_NE(input_error_message([&] {
              read("field: {type: slant, angle_degrees: 400}");
            }).find("field.angle_degrees: expected"),
            std::string::npos);
  // A key of another type is unknown here, with a hint.
  EXPECT_NE(input_error_message([&] {
              read("field: {type: slant, ratio: 2}");
            }).find("unknown key 'field.ratio'"),
            std::string::npos);
  EXPECT_NE(input_error_message([&] {
              read("field: {type: slant, angel_degrees: 2}");
            }).find("did you mean 'field.angle_degrees'"),
            std::string::npos);
  EXPECT_NE(input_error_message([&] {
              read("field: {type: file}");
            }).find("field.file: expected a string (required key is missing)"),
            std::string::npos);

  const auto dir = test::scratch_dir("anisometric_field_errors");
  EXPECT_NE(input_error_message([&] {
              read("field: {type: file, file: " + (dir / "none.vti").string() + "}");
            }).find("field.file: expected an existing vector field file"),
            std::string::npos);
  EXPECT_NE(input_error_message([&] {
              read("field: {type: file, file: field.txt}");
            }).find("field.file: expected a vector field file (.vdb, .vti, .h5 or .hdf5)"),
            std::string::npos);

  const auto scalar = dir / "density.vti";
  vol::write_vti(scalar, vol::ScalarGrid({2, 2, 2}, 1.0f), "density");
  const std::string scalar_message =
      input_error_message([&] { read("field: {type: file, file: " + scalar.string() + "}"); });
  EXPECT_NE(scalar_message.find("field.file: "), std::string::npos) << scalar_message;
  EXPECT_NE(scalar_message.find(scalar.string()), std::string::npos) << scalar_message;

  const auto broken = dir / "broken.h5";
  std::ofstream(broken) << "not hdf5";
  const std::string broken_message =
      input_error_message([&] { read("field: {type: file, file: " + broken.string() + "}"); });
  EXPECT_EQ(broken_message.rfind("field.file: ", 0), 0u) << broken_message;
  EXPECT_NE(broken_message.find(broken.string()), std::string::npos) << broken_message;
}

} // namespace
} // namespace texsim::pipelines::solid_synthesis
