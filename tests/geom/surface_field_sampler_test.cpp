// Per-vertex fields of mesh files (read_vertex_fields) and their values at points of nearby
// surfaces (SurfaceFieldSampler). A linear field is reproduced exactly on the file's surface, and
// off it the error is bounded by |grad f| times the distance to the surface (the closest point's
// value is exact, so only the normal offset counts).
#include "core/rng.hpp"
#include "geom/aabb_tree.hpp"
#include "geom/generators.hpp"
#include "geom/loop_subdivision.hpp"
#include "geom/mesh_reader.hpp"
#include "geom/random_surface_points.hpp"
#include "geom/surface_field_sampler.hpp"
#include "support/input_error.hpp"
#include "support/vtp_file.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include <unistd.h>

namespace texsim::geom {
namespace {
namespace fs = std::filesystem;

const Vec3 kGradient(0.3, -0.2, 0.1);
double linear_field(const Vec3& p) {
  return 1.0 + kGradient.dot(p);
}

/// An ASCII VTK XML polydata file with the point array `name` = linear_field.
fs::path write_vtp(const fs::path& path, const TriangleMesh& mesh, const std::string& name) {
  std::vector<double> values;
  for (const auto& p : mesh.positions)
    values.push_back(linear_field(p));
  return test::write_vtp(path, mesh, {{name, values}});
}

/// A legacy ASCII VTK polydata file with one point array.
fs::path write_legacy_vtk(const fs::path& path, const TriangleMesh& mesh, const std::string& name) {
  std::ofstream out(path);
  out.precision(17);
  out << "# vtk DataFile Version 3.0\nfield test\nASCII\nDATASET POLYDATA\nPOINTS "
      << mesh.positions.size() << " double\n";
  for (const auto& p : mesh.positions)
    out << p.x() << " " << p.y() << " " << p.z() << "\n";
  out << "POLYGONS " << mesh.triangles.size() << " " << 4 * mesh.triangles.size() << "\n";
  for (const auto& t : mesh.triangles)
    out << "3 " << t[0] << " " << t[1] << " " << t[2] << "\n";
  out << "POINT_DATA " << mesh.positions.size() << "\nSCALARS " << name
      << " double 1\nLOOKUP_TABLE default\n";
  for (const auto& p : mesh.positions)
    out << linear_field(p) << "\n";
  return path;
}

fs::path scratch_dir() {
  const auto dir = fs::temp_directory_path() / ("texsim_field_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  return dir;
}

TEST(VertexFields, ReadFromVtpAndLegacyVtkWithTheirTriangles) {
  const auto mesh = icosphere(2);
  const auto dir = scratch_dir();
  for (const auto& file : {write_vtp(dir / "sphere.vtp", mesh, "width"),
                           write_legacy_vtk(dir / "sphere.vtk", mesh, "width")}) {
    SCOPED_TRACE(file.string());
    const auto fields = read_vertex_fields(file, {"width"});
    ASSERT_EQ(fields.mesh.positions.size(), mesh.positions.size());
    ASSERT_EQ(fields.mesh.triangles.size(), mesh.triangles.size());
    ASSERT_EQ(fields.values.size(), 1u);
    for (std::size_t v = 0; v < mesh.positions.size(); ++v)
      EXPECT_NEAR(fields.values[0][v], linear_field(fields.mesh.positions[v]), 1e-6);
  }
  fs::remove_all(dir);
}

TEST(VertexFields, MissingArrayAndUnsupportedFormatNameTheFile) {
  const auto mesh = icosphere(1);
  const auto dir = scratch_dir();
  const auto vtp = write_vtp(dir / "sphere.vtp", mesh, "width");
  const auto missing = test::input_error_message([&] { read_vertex_fields(vtp, {"height"}); });
  EXPECT_NE(missing.find("sphere.vtp"), std::string::npos) << missing;
  EXPECT_NE(missing.find("'height'"), std::string::npos) << missing;
  EXPECT_NE(missing.find("width"), std::string::npos) << missing; // lists what the file has
  for (const char* name : {"x.off", "x.ply"}) {
    const auto other = test::input_error_message([&] { read_vertex_fields(dir / name, {"w"}); });
    EXPECT_NE(other.find(name), std::string::npos) << other;
    EXPECT_NE(other.find(".vtp, .vtu and .vtk"), std::string::npos) << other;
  }
  fs::remove_all(dir);
}

TEST(SurfaceFieldSampler, LinearFieldExactOnTheSurfaceAndBoundedOffIt) {
  const auto coarse = icosphere(2);
  std::vector<double> values;
  for (const auto& p : coarse.positions)
    values.push_back(linear_field(p));
  const SurfaceFieldSampler sampler(coarse, {values});

  // Points on the file's own surface (and its vertices): the interpolant is the field itself.
  std::vector<Vec3> on_surface(coarse.positions);
  for (const auto& p : random_surface_points(coarse, 0, 500, 11))
    on_surface.push_back(p.position);
  const auto exact = sampler.sample(0, on_surface);
  for (std::size_t i = 0; i < on_surface.size(); ++i)
    ASSERT_NEAR(exact[i], linear_field(on_surface[i]), 1e-13) << "point " << i;

  // Vertices of a refined copy lie off the coarse surface: the error is the gradient times the
  // offset to the closest point, and no more.
  const auto fine = loop_subdivide(coarse, 2);
  const AabbTree tree(coarse);
  const auto sampled = sampler.sample(0, fine.positions);
  double largest_offset = 0;
  for (std::size_t i = 0; i < fine.positions.size(); ++i) {
    const double offset = tree.closest_point(fine.positions[i]).distance;
    largest_offset = std::max(largest_offset, offset);
    ASSERT_LE(std::abs(sampled[i] - linear_field(fine.positions[i])),
              kGradient.norm() * offset + 1e-13)
        << "vertex " << i;
  }
  EXPECT_GT(largest_offset, 1e-3); // the refined vertices really are off the coarse surface
}

} // namespace
} // namespace texsim::geom
