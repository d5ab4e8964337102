#include "pipelines/fluid_lapped/patch_exchange.hpp"

#include "par/morton_partition.hpp"
#include "par/record_exchange.hpp"

#include <mpi.h>

#include <algorithm>
#include <map>
#include <numeric>

namespace texsim::pipelines::fluid_lapped {
namespace {

struct VertexRecord {
  std::int64_t patch;
  std::int32_t birth_frame;
  std::int32_t surface_triangle;
  double position[3];
  double rest_uv[2];
  double weight;
};

struct TriangleRecord {
  std::int64_t patch;
  std::int32_t corners[3];
};

/// Appends the records of `patch` to the two lists.
void pack(const Patch& patch, std::vector<VertexRecord>& vertices,
          std::vector<TriangleRecord>& triangles) {
  for (std::size_t v = 0; v < patch.positions.size(); ++v) {
    const auto& p = patch.positions[v];
    const auto& uv = patch.rest_uv[v];
    vertices.push_back({patch.id,
                        patch.birth_frame,
                        patch.surface_triangle[v],
                        {p.x(), p.y(), p.z()},
                        {uv.x(), uv.y()},
                        patch.weights[v]});
  }
  for (const auto& t : patch.triangles)
    triangles.push_back({patch.id, {t[0], t[1], t[2]}});
}

/// Puts patches together from their records; records of one patch keep their relative order
/// (they come from one sender), so vertex and triangle numbering survives the trip.
std::vector<Patch> unpack(const std::vector<VertexRecord>& vertices,
                          const std::vector<TriangleRecord>& triangles) {
  std::map<std::int64_t, Patch> by_id;
  for (const auto& r : vertices) {
    auto& patch = by_id[r.patch];
    patch.id = r.patch;
    patch.birth_frame = r.birth_frame;
    patch.positions.emplace_back(r.position[0], r.position[1], r.position[2]);
    patch.surface_triangle.push_back(r.surface_triangle);
    patch.rest_uv.emplace_back(r.rest_uv[0], r.rest_uv[1]);
    patch.weights.push_back(r.weight);
  }
  for (const auto& r : triangles)
    by_id.at(r.patch).triangles.push_back({r.corners[0], r.corners[1], r.corners[2]});
  std::vector<Patch> patches;
  patches.reserve(by_id.size());
  for (auto& [id, patch] : by_id)
    patches.push_back(std::move(patch));
  return patches;
}

} // namespace

std::vector<Patch> exchange_patches(const par::Comm& comm, std::span<const Patch> patches,
                                    std::span<const int> destination) {
  std::vector<std::vector<VertexRecord>> vertices(std::size_t(comm.size));
  std::vector<std::vector<TriangleRecord>> triangles(std::size_t(comm.size));
  for (std::size_t i = 0; i < patches.size(); ++i)
    pack(patches[i], vertices[std::size_t(destination[i])], triangles[std::size_t(destination[i])]);
  return unpack(par::exchange_records(comm, vertices), par::exchange_records(comm, triangles));
}

std::vector<int> morton_destinations(const par::Comm& comm, std::span<const Patch> patches) {
  struct Centre {
    std::int64_t id;
    std::array<double, 3> xyz;
  };
  std::vector<Centre> local;
  for (const auto& patch : patches) {
    geom::Vec3 sum = geom::Vec3::Zero();
    for (const auto& p : patch.positions)
      sum += p;
    sum /= double(std::max<std::size_t>(patch.positions.size(), 1));
    local.push_back({patch.id, {sum.x(), sum.y(), sum.z()}});
  }
  auto all = par::allgather_records(comm, local);
  std::sort(all.begin(), all.end(), [](const Centre& a, const Centre& b) { return a.id < b.id; });
  std::vector<std::array<double, 3>> points;
  for (const auto& c : all)
    points.push_back(c.xyz);
  const auto parts = par::morton_partition(points, comm.size);
  std::vector<int> destination;
  for (const auto& patch : patches) {
    const auto at = std::lower_bound(all.begin(), all.end(), patch.id,
                                     [](const Centre& c, std::int64_t id) { return c.id < id; });
    destination.push_back(parts[std::size_t(at - all.begin())]);
  }
  return destination;
}

std::vector<int> id_order_destinations(const par::Comm& comm, std::span<const Patch> patches) {
  struct Size {
    std::int64_t id;
    std::int64_t vertices;
  };
  std::vector<Size> local;
  for (const auto& patch : patches)
    local.push_back({patch.id, std::int64_t(patch.positions.size())});
  auto all = par::allgather_records(comm, local);
  std::sort(all.begin(), all.end(), [](const Size& a, const Size& b) { return a.id < b.id; });
  std::int64_t total = 0;
  for (const auto& s : all)
    total += s.vertices;
  // Patch k goes to the rank whose share of the vertex total holds the patch's first vertex.
  std::map<std::int64_t, int> rank_of;
  std::int64_t before = 0;
  for (const auto& s : all) {
    rank_of[s.id] =
        total == 0 ? 0 : int(std::min<std::int64_t>(before * comm.size / total, comm.size - 1));
    before += s.vertices;
  }
  std::vector<int> destination;
  for (const auto& patch : patches)
    destination.push_back(rank_of.at(patch.id));
  return destination;
}

} // namespace texsim::pipelines::fluid_lapped
