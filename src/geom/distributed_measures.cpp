#include "geom/distributed_measures.hpp"

#include "geom/mesh_measures.hpp"
#include "geom/surface_roughness.hpp"
#include "par/reproducible_sum.hpp"

#include <mpi.h>

#include <algorithm>
#include <vector>

namespace texsim::geom {
namespace {

/// {sum, count} summed over ranks.
std::pair<double, double> summed(const DistributedMesh& mesh, double sum, double count) {
  double local[2] = {sum, count}, total[2];
  MPI_Allreduce(local, total, 2, MPI_DOUBLE, MPI_SUM, mesh.comm().raw);
  return {total[0], total[1]};
}

} // namespace

double total_area(const DistributedMesh& mesh) {
  const auto& surface = mesh.mesh();
  double area = 0;
  for (const std::int32_t t : mesh.owned_triangles()) {
    const auto& tri = surface.triangles[t];
    area += triangle_area(surface.positions[tri[0]], surface.positions[tri[1]],
                          surface.positions[tri[2]]);
  }
  return summed(mesh, area, 0).first;
}

std::int64_t boundary_edge_count(const DistributedMesh& mesh) {
  // An owned triangle's edge inside the surface has its second triangle in the halo.
  const auto& topology = mesh.topology();
  std::int64_t mine = 0;
  for (const std::int32_t t : mesh.owned_triangles())
    for (const std::int32_t e : topology.triangle_edges(t))
      if (topology.edge_triangles(e).size() == 1)
        ++mine;
  std::int64_t total = 0;
  MPI_Allreduce(&mine, &total, 1, MPI_INT64_T, MPI_SUM, mesh.comm().raw);
  return total;
}

std::int64_t crease_edge_count(const DistributedMesh& mesh) {
  // A crease lies between two triangles, each owned by exactly one rank: counted twice.
  std::int64_t mine = 0;
  if (!mesh.creases().empty())
    for (const std::int32_t t : mesh.owned_triangles())
      for (const std::int32_t e : mesh.topology().triangle_edges(t))
        mine += mesh.creases()[std::size_t(e)];
  std::int64_t total = 0;
  MPI_Allreduce(&mine, &total, 1, MPI_INT64_T, MPI_SUM, mesh.comm().raw);
  return total / 2;
}

double mean_edge_length(const DistributedMesh& mesh) {
  const auto& surface = mesh.mesh();
  std::vector<double> lengths;
  lengths.reserve(3 * mesh.owned_triangles().size());
  for (const std::int32_t t : mesh.owned_triangles()) {
    const auto& tri = surface.triangles[t];
    for (int i = 0; i < 3; ++i)
      lengths.push_back((surface.positions[tri[(i + 1) % 3]] - surface.positions[tri[i]]).norm());
  }
  const double edges = 3.0 * double(mesh.global_triangle_count());
  return edges > 0 ? par::reproducible_sum(mesh.comm(), lengths) / edges : 0.0;
}

double mean_normal_deviation_deg(const DistributedMesh& mesh) {
  // An edge counts on the rank owning its smaller global vertex, which holds both its triangles.
  const auto& edges = mesh.topology().edges();
  const auto local = normal_deviation_sum(mesh.mesh(), mesh.topology(), [&](std::int32_t e) {
    const std::int32_t smaller =
        std::min(mesh.global_index(edges[e][0]), mesh.global_index(edges[e][1]));
    return smaller >= mesh.owned_begin() && smaller < mesh.owned_end();
  });
  const auto [radians, count] = summed(mesh, local.radians, double(local.edges));
  return mean_degrees({radians, std::int64_t(count)});
}

} // namespace texsim::geom
