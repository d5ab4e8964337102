#include "geom/distributed_mesh_fields.hpp"

#include "core/error.hpp"
#include "par/collective.hpp"

#include <mpi.h>

#include <algorithm>
#include <cmath>
#include <limits>

namespace texsim::geom {
namespace {

/// What a rank asks rank 0 for: whether it needs triangles, and its points' box.
struct Request {
  double needed = 0;
  double lower[3] = {0, 0, 0};
  double upper[3] = {0, 0, 0};
};

constexpr int kCropTag = 7041;

/// The packed crop as a mesh with values.
VertexFields unpack(const std::vector<double>& packed, bool& whole) {
  const auto vertices = std::size_t(packed[0]), triangles = std::size_t(packed[1]),
             fields = std::size_t(packed[2]);
  whole = packed[3] != 0;
  VertexFields crop;
  std::size_t at = 4;
  for (std::size_t v = 0; v < vertices; ++v, at += 3)
    crop.mesh.positions.emplace_back(packed[at], packed[at + 1], packed[at + 2]);
  for (std::size_t t = 0; t < triangles; ++t, at += 3)
    crop.mesh.triangles.push_back(
        {std::int32_t(packed[at]), std::int32_t(packed[at + 1]), std::int32_t(packed[at + 2])});
  for (std::size_t k = 0; k < fields; ++k, at += vertices)
    crop.values.emplace_back(packed.begin() + std::ptrdiff_t(at),
                             packed.begin() + std::ptrdiff_t(at + vertices));
  return crop;
}

} // namespace

DistributedMeshFields::DistributedMeshFields(const par::Comm& comm, const MeshSource& mesh,
                                             const std::vector<std::string>& names)
    : comm_(comm), field_count_(names.size()) {
  double margin = 0;
  par::run_collectively(comm, [&] {
    if (!comm.is_root())
      return;
    file_ = read_vertex_fields(mesh.file, names);
    if (file_->mesh.triangles.empty())
      throw InputError(mesh.file.string() + ": no triangles to take mesh_fields from");
    Eigen::AlignedBox3d all;
    for (auto& position : file_->mesh.positions) {
      position *= mesh.scale;
      all.extend(position);
    }
    for (const auto& tri : file_->mesh.triangles) {
      Eigen::AlignedBox3d box;
      for (const std::int32_t v : tri)
        box.extend(file_->mesh.positions[std::size_t(v)]);
      triangle_boxes_.push_back(box);
    }
    margin = 0.01 * all.diagonal().norm();
  });
  MPI_Bcast(&margin, 1, MPI_DOUBLE, 0, comm.raw);
  initial_margin_ = margin;
}

std::vector<double> DistributedMeshFields::crop(const Eigen::AlignedBox3d& box,
                                                double margin) const {
  const Eigen::Vector3d grow = Eigen::Vector3d::Constant(margin);
  const Eigen::AlignedBox3d reach(box.min() - grow, box.max() + grow);
  const auto& surface = file_->mesh;
  std::vector<std::int32_t> kept, vertex_of(surface.positions.size(), -1), vertices;
  for (std::size_t t = 0; t < surface.triangles.size(); ++t)
    if (reach.intersects(triangle_boxes_[t])) {
      kept.push_back(std::int32_t(t));
      for (const std::int32_t v : surface.triangles[t])
        if (vertex_of[std::size_t(v)] < 0) {
          vertex_of[std::size_t(v)] = std::int32_t(vertices.size());
          vertices.push_back(v);
        }
    }
  std::vector<double> packed{double(vertices.size()), double(kept.size()), double(field_count_),
                             kept.size() == surface.triangles.size() ? 1.0 : 0.0};
  for (const std::int32_t v : vertices)
    packed.insert(packed.end(), surface.positions[std::size_t(v)].data(),
                  surface.positions[std::size_t(v)].data() + 3);
  for (const std::int32_t t : kept)
    for (const std::int32_t v : surface.triangles[std::size_t(t)])
      packed.push_back(vertex_of[std::size_t(v)]);
  for (const auto& field : file_->values)
    for (const std::int32_t v : vertices)
      packed.push_back(field[std::size_t(v)]);
  return packed;
}

std::vector<std::vector<double>> DistributedMeshFields::sample(std::span<const Vec3> points) const {
  Eigen::AlignedBox3d box;
  for (const auto& p : points)
    box.extend(p);
  std::vector<std::vector<double>> values(field_count_, std::vector<double>(points.size()));
  bool done = points.empty();
  double margin = initial_margin_;
  std::vector<Request> requests(comm_.is_root() ? std::size_t(comm_.size) : 0);
  while (true) {
    Request mine;
    mine.needed = done ? 0 : 1;
    if (!done)
      for (int axis = 0; axis < 3; ++axis) {
        mine.lower[axis] = box.min()[axis];
        mine.upper[axis] = box.max()[axis];
      }
    MPI_Gather(&mine, 7, MPI_DOUBLE, requests.data(), 7, MPI_DOUBLE, 0, comm_.raw);
    std::vector<double> packed;
    if (comm_.is_root()) {
      std::vector<MPI_Request> sends;
      std::vector<std::vector<double>> outgoing(std::size_t(comm_.size));
      for (int rank = 0; rank < comm_.size; ++rank) {
        const Request& request = requests[std::size_t(rank)];
        if (request.needed == 0)
          continue;
        const Eigen::AlignedBox3d asked(Eigen::Vector3d(request.lower),
                                        Eigen::Vector3d(request.upper));
        if (rank == 0) {
          packed = crop(asked, margin);
          continue;
        }
        outgoing[std::size_t(rank)] = crop(asked, margin);
        sends.emplace_back();
        MPI_Isend(outgoing[std::size_t(rank)].data(), int(outgoing[std::size_t(rank)].size()),
                  MPI_DOUBLE, rank, kCropTag, comm_.raw, &sends.back());
      }
      MPI_Waitall(int(sends.size()), sends.data(), MPI_STATUSES_IGNORE);
    } else if (!done) {
      MPI_Status status;
      MPI_Probe(0, kCropTag, comm_.raw, &status);
      int count = 0;
      MPI_Get_count(&status, MPI_DOUBLE, &count);
      packed.resize(std::size_t(count));
      MPI_Recv(packed.data(), count, MPI_DOUBLE, 0, kCropTag, comm_.raw, MPI_STATUS_IGNORE);
    }
    // The distance this rank still needs as a margin (0: done; infinity: no triangle came).
    double needed = 0;
    if (!done) {
      bool whole = false;
      auto near = unpack(packed, whole);
      if (near.mesh.triangles.empty()) {
        needed = std::numeric_limits<double>::infinity();
      } else {
        const SurfaceFieldSampler sampler(near.mesh, std::move(near.values));
        auto sampled = sampler.sample_all(points);
        if (whole || sampled.max_distance <= margin) {
          values = std::move(sampled.values);
          done = true;
        } else {
          needed = sampled.max_distance;
        }
      }
    }
    double largest = 0;
    MPI_Allreduce(&needed, &largest, 1, MPI_DOUBLE, MPI_MAX, comm_.raw);
    if (largest == 0)
      return values;
    margin = std::isfinite(largest) ? std::max(largest, 2 * margin) : 4 * margin;
  }
}

} // namespace texsim::geom
