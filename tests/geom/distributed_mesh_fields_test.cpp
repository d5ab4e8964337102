// Mesh-file fields sampled for points spread over ranks with only rank 0 holding the file: the
// values equal those of sampling the whole file, for points on, near and far from the surface
// (far ones need a wider margin and a second round) and for a rank without points.
#include "core/error.hpp"
#include "geom/distributed_mesh_fields.hpp"
#include "geom/generators.hpp"
#include "par/comm.hpp"
#include "support/test_data.hpp"
#include "support/vtp_file.hpp"

#include <gtest/gtest.h>

#include <cmath>

namespace texsim::geom {
namespace {
namespace fs = std::filesystem;

/// A noisy sphere with two fields, written by rank 0; its mesh on every rank.
TriangleMesh write_surface(const par::Comm& comm, const fs::path& path,
                           std::vector<std::vector<double>>& values) {
  const TriangleMesh mesh = noisy(icosphere(3), 0.1, 11);
  values.assign(2, {});
  for (const auto& p : mesh.positions) {
    values[0].push_back(p.x() + 2 * p.y() * p.z());
    values[1].push_back(std::sin(3 * p.z()));
  }
  if (comm.is_root())
    test::write_vtp(path, mesh, {{"f", values[0]}, {"g", values[1]}});
  comm.barrier();
  return mesh;
}

/// This rank's points: rank r takes every (r+1)-th of a spiral at radii near and far from the
/// sphere; the last rank of three takes none.
std::vector<Vec3> points_of(const par::Comm& comm) {
  std::vector<Vec3> points;
  if (comm.size == 3 && comm.rank == 2)
    return points;
  for (int i = 0; i < 600; ++i) {
    if (i % comm.size != comm.rank)
      continue;
    const double z = -1 + 2 * (i + 0.5) / 600, phi = 2.399963 * i;
    const double radius = i % 7 == 0 ? 4.0 : 0.9 + 0.2 * ((i * 37) % 11) / 10.0;
    const double r = std::sqrt(1 - z * z);
    points.push_back(radius * Vec3(r * std::cos(phi), r * std::sin(phi), z));
  }
  return points;
}

TEST(DistributedMeshFields, EqualTheWholeFilesValues) {
  const par::Comm comm = par::world();
  const fs::path path = test::scratch_dir("geom_distributed_mesh_fields") / "sphere.vtp";
  std::vector<std::vector<double>> values;
  const TriangleMesh mesh = write_surface(comm, path, values);
  MeshSource source;
  source.file = path;
  const DistributedMeshFields fields(comm, source, {"g", "f"});
  EXPECT_EQ(fields.field_count(), 2u);
  const auto points = points_of(comm);
  const auto sampled = fields.sample(points);
  ASSERT_EQ(sampled.size(), 2u);
  const SurfaceFieldSampler whole(mesh, {values[1], values[0]});
  for (std::size_t k = 0; k < 2; ++k) {
    const auto expected = whole.sample(k, points);
    ASSERT_EQ(sampled[k].size(), expected.size());
    for (std::size_t i = 0; i < expected.size(); ++i)
      EXPECT_NEAR(sampled[k][i], expected[i], 1e-12) << "field " << k << " point " << i;
  }
}

TEST(DistributedMeshFields, AScaledFileAndAMissingArray) {
  const par::Comm comm = par::world();
  const fs::path path = test::scratch_dir("geom_distributed_mesh_fields") / "scaled.vtp";
  std::vector<std::vector<double>> values;
  TriangleMesh mesh = write_surface(comm, path, values);
  MeshSource source;
  source.file = path;
  source.scale = 3.0;
  const DistributedMeshFields fields(comm, source, {"f"});
  for (auto& p : mesh.positions)
    p *= 3.0;
  const SurfaceFieldSampler whole(mesh, {values[0]});
  const auto points = points_of(comm);
  std::vector<Vec3> scaled;
  for (const auto& p : points)
    scaled.push_back(3.0 * p);
  const auto expected = whole.sample(0, scaled);
  const auto sampled = fields.sample(scaled);
  for (std::size_t i = 0; i < expected.size(); ++i)
    EXPECT_NEAR(sampled[0][i], expected[i], 1e-12);
  // Every rank gets the file's error, not only rank 0 that reads it.
  EXPECT_THROW(DistributedMeshFields(comm, source, {"missing"}), InputError);
}

} // namespace
} // namespace texsim::geom
