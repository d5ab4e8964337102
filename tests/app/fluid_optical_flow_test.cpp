// fluid_lapped's images through the binary. Every covered texel of an atlas shows the exemplar
// texel under the (patch, uv) its patch-id image records, and the 16-bit displacement image the
// displacement exemplar's there. Gagnon et al. 2021, Fig. 16: the texture follows the fluid. The
// plane vortex with the identity chart (atlas = orthographic rendering of the square) is run; the
// pyramidal Lucas-Kanade flow between consecutive atlas images is compared with the flow's own
// displacement of each texel's point over the frame, where the texel shows the same patch in
// both frames. The Lucas-Kanade code is first checked on a known sub-pixel translation.
#include "img/image_io.hpp"
#include "pipelines/fluid_lapped/analytic_flows.hpp"
#include "support/optical_flow.hpp"
#include "support/run_command.hpp"

#include <gtest/gtest.h>
#include <vtkDataArray.h>
#include <vtkImageData.h>
#include <vtkNew.h>
#include <vtkPNGReader.h>
#include <vtkPointData.h>
#include <vtkXMLPImageDataReader.h>

#include <algorithm>
#include <cmath>
#include <filesystem>

namespace {
namespace fs = std::filesystem;
using texsim::test::GreyPicture;
using texsim::test::LucasKanade;

const fs::path kSource = TEXSIM_SOURCE_DIR;

/// A smooth texture, two crossing waves, moved by (shift_x, shift_y) pixels.
GreyPicture waves(int size, double shift_x, double shift_y) {
  GreyPicture picture{size, size, std::vector<float>(std::size_t(size) * size)};
  for (int y = 0; y < size; ++y)
    for (int x = 0; x < size; ++x) {
      const double u = x - shift_x, v = y - shift_y;
      picture.values[std::size_t(y) * size + x] =
          float(0.5 + 0.3 * std::sin(0.2 * u + 0.1 * v) + 0.2 * std::cos(0.15 * v - 0.05 * u));
    }
  return picture;
}

double median(std::vector<double> values) {
  std::nth_element(values.begin(), values.begin() + values.size() / 2, values.end());
  return values[values.size() / 2];
}

TEST(LucasKanade, RecoversASubPixelTranslation) {
  const auto first = waves(96, 0, 0), second = waves(96, 1.3, -0.7);
  const LucasKanade flow(first, second);
  std::vector<double> errors;
  int tried = 0;
  for (int y = 16; y < 80; y += 4)
    for (int x = 16; x < 80; x += 4, ++tried)
      if (const auto d = flow.at(x, y); d.valid)
        errors.push_back(std::hypot(d.dx - 1.3, d.dy + 0.7));
  EXPECT_GT(double(errors.size()), 0.8 * tried);
  EXPECT_LT(median(errors), 0.1);
}

GreyPicture luminance(const fs::path& png) {
  const auto image = texsim::img::read_image(png);
  GreyPicture grey{image.width(), image.height(), {}};
  for (const auto& c : image.data())
    grey.values.push_back(0.2126f * c.r + 0.7152f * c.g + 0.0722f * c.b);
  return grey;
}

/// Component `component` of array `name` of a frame's patch-id image, rows from the top like the
/// PNG.
std::vector<double> texel_array(const fs::path& vti, const char* name, int component = 0) {
  vtkNew<vtkXMLPImageDataReader> reader;
  reader->SetFileName(vti.c_str());
  reader->Update();
  auto* image = reader->GetOutput();
  int dims[3];
  image->GetDimensions(dims);
  auto* values = image->GetPointData()->GetArray(name);
  std::vector<double> top_down(std::size_t(dims[0]) * dims[1]);
  for (int j = 0; j < dims[1]; ++j)
    for (int i = 0; i < dims[0]; ++i)
      top_down[std::size_t(dims[1] - 1 - j) * dims[0] + i] =
          values->GetComponent(vtkIdType(j) * dims[0] + i, component);
  return top_down;
}

std::vector<std::int64_t> patch_ids(const fs::path& vti) {
  const auto values = texel_array(vti, "patch_id");
  return {values.begin(), values.end()};
}

TEST(FluidLappedOutputs, EveryCoveredTexelShowsTheExemplarTexelAtItsPatchUv) {
  const auto out = fs::temp_directory_path() / "texsim_fluid_outputs";
  fs::remove_all(out);
  const fs::path exemplar = kSource / "data/images/pebbles05.png";
  const fs::path heights = kSource / "data/images/rock01.png";
  const auto run = texsim::test::run_command(
      texsim::test::texsim_under_mpirun(3) + " " +
          (kSource / "config/fluid_lapped/sphere_shear.yaml").string() +
          " --quiet --set fluid_lapped.frames.count=2 --set fluid_lapped.frames.mesh.level=3"
          " --set fluid_lapped.atlas.resolution=192 --set fluid_lapped.atlas.tile=64"
          " --set fluid_lapped.exemplar.image=" +
          exemplar.string() + " --set fluid_lapped.exemplar.displacement=" + heights.string() +
          " --set output.every=1 --set output.dir=" + out.string(),
      kSource);
  ASSERT_EQ(run.exit_code, 0) << run.output;
  const auto colours = texsim::img::read_image(exemplar);
  const auto displacement = texsim::img::read_image(heights);
  const int w = colours.width(), h = colours.height();
  for (const char* frame : {"0000", "0001"}) {
    const auto atlas =
        texsim::img::read_image(out / (std::string("atlas/atlas_") + frame + ".png"));
    const auto ids =
        texel_array(out / (std::string("patch_ids/patch_ids_") + frame + ".pvti"), "patch_id");
    const auto u =
        texel_array(out / (std::string("patch_ids/patch_ids_") + frame + ".pvti"), "uv", 0);
    const auto v =
        texel_array(out / (std::string("patch_ids/patch_ids_") + frame + ".pvti"), "uv", 1);
    vtkNew<vtkPNGReader> png16;
    png16->SetFileName(
        (out / (std::string("displacement/displacement_") + frame + ".png")).c_str());
    png16->Update();
    auto* height_values = png16->GetOutput()->GetPointData()->GetScalars();
    ASSERT_EQ(height_values->GetDataType(), VTK_UNSIGNED_SHORT);
    std::size_t covered = 0;
    for (int y = 0; y < atlas.height(); ++y)
      for (int x = 0; x < atlas.width(); ++x) {
        const auto i = std::size_t(y) * atlas.width() + x;
        if (ids[i] < 0)
          continue;
        ++covered;
        // The exemplar spans uv [0, 1]^2 with v up and repeats: the texel holding (u, v).
        const auto wrap = [](double t, int n) {
          return int(((long(std::floor(t * n)) % n) + n) % n);
        };
        const int ex = wrap(float(u[i]), w), ey = h - 1 - wrap(float(v[i]), h);
        const auto& want = colours.at(ex, ey);
        const auto& got = atlas.at(x, y);
        ASSERT_EQ(std::lround(got.r * 255), std::lround(want.r * 255)) << x << ", " << y;
        ASSERT_EQ(std::lround(got.g * 255), std::lround(want.g * 255)) << x << ", " << y;
        ASSERT_EQ(std::lround(got.b * 255), std::lround(want.b * 255)) << x << ", " << y;
        const auto& rock = displacement.at(ex, ey);
        const double luminance = 0.2126f * rock.r + 0.7152f * rock.g + 0.0722f * rock.b;
        EXPECT_NEAR(height_values->GetTuple1(vtkIdType(atlas.height() - 1 - y) * atlas.width() + x),
                    65535 * luminance, 1.0);
      }
    EXPECT_GT(covered, std::size_t(atlas.width() * atlas.height() / 3));
  }
}

TEST(FluidLappedOpticalFlow, TheTextureMovesWithTheVortex) {
  const auto out = fs::temp_directory_path() / "texsim_fluid_optical_flow";
  fs::remove_all(out);
  constexpr int kSize = 256;
  constexpr double kInterval = 0.02;
  const auto run = texsim::test::run_command(
      texsim::test::texsim_under_mpirun(2) + " " +
          (kSource / "config/fluid_lapped/vortex_plane.yaml").string() +
          " --quiet --set fluid_lapped.frames.count=3 --set fluid_lapped.frames.interval=" +
          std::to_string(kInterval) +
          " --set fluid_lapped.atlas.resolution=" + std::to_string(kSize) +
          " --set fluid_lapped.radius=0.15 --set output.every=1"
          " --set output.dir=" +
          out.string(),
      kSource);
  ASSERT_EQ(run.exit_code, 0) << run.output;
  // The same flow as the config's.
  texsim::pipelines::fluid_lapped::AnalyticFlowSettings vortex;
  vortex.kind = texsim::pipelines::fluid_lapped::FlowKind::plane_vortex;
  vortex.centre = {0.5, 0.5, 0};
  vortex.rate = 3.0;
  vortex.width = 0.25;
  vortex.period = 2.0;
  const auto velocity = texsim::pipelines::fluid_lapped::make_analytic_flow(vortex);
  for (int k = 0; k + 1 < 3; ++k) {
    char a[64], b[64], ia[64], ib[64];
    std::snprintf(a, sizeof a, "atlas/atlas_%04d.png", k);
    std::snprintf(b, sizeof b, "atlas/atlas_%04d.png", k + 1);
    std::snprintf(ia, sizeof ia, "patch_ids/patch_ids_%04d.pvti", k);
    std::snprintf(ib, sizeof ib, "patch_ids/patch_ids_%04d.pvti", k + 1);
    const LucasKanade flow(luminance(out / a), luminance(out / b));
    const auto ids_a = patch_ids(out / ia), ids_b = patch_ids(out / ib);
    std::vector<double> endpoint, angle;
    std::size_t same_patch = 0, compared = 0;
    for (int y = 24; y < kSize - 24; y += 3)
      for (int x = 24; x < kSize - 24; x += 3) {
        ++compared;
        // The texel's point carried over the frame by the flow (RK4, 20 steps).
        Eigen::Vector3d p((x + 0.5) / kSize, 1.0 - (y + 0.5) / kSize, 0.0);
        const Eigen::Vector3d start = p;
        const double h = kInterval / 20;
        for (int s = 0; s < 20; ++s) {
          const double t = k * kInterval + s * h;
          const auto k1 = velocity->at(p, t), k2 = velocity->at(p + 0.5 * h * k1, t + 0.5 * h);
          const auto k3 = velocity->at(p + 0.5 * h * k2, t + 0.5 * h),
                     k4 = velocity->at(p + h * k3, t + h);
          p += h / 6 * (k1 + 2 * k2 + 2 * k3 + k4);
        }
        const double tx = (p.x() - start.x()) * kSize, ty = -(p.y() - start.y()) * kSize;
        const int xb = int(std::lround(x + tx)), yb = int(std::lround(y + ty));
        if (ids_a[std::size_t(y) * kSize + x] != ids_b[std::size_t(yb) * kSize + xb])
          continue;
        ++same_patch;
        const auto d = flow.at(x, y);
        if (!d.valid)
          continue;
        endpoint.push_back(std::hypot(d.dx - tx, d.dy - ty));
        if (std::hypot(tx, ty) >= 1.0)
          angle.push_back(
              std::abs(std::remainder(std::atan2(d.dy, d.dx) - std::atan2(ty, tx), 2 * M_PI)) *
              180 / M_PI);
      }
    EXPECT_GE(double(same_patch), 0.85 * double(compared)) << "frame " << k;
    ASSERT_GT(angle.size(), 100u);
    double mean_angle = 0;
    for (const double a_deg : angle)
      mean_angle += a_deg / double(angle.size());
    EXPECT_LE(mean_angle, 10.0) << "frame " << k;
    EXPECT_LE(median(endpoint), 0.5) << "frame " << k;
    std::printf("frame %d -> %d: %zu of %zu texels keep their patch, mean angular error %.2f deg, "
                "median endpoint error %.3f texel\n",
                k, k + 1, same_patch, compared, mean_angle, median(endpoint));
  }
}

} // namespace
