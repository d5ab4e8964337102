#include "geom/point_halo.hpp"

#include "core/error.hpp"

#include <mpi.h>

#include <algorithm>
#include <array>

namespace texsim::geom {
namespace {

// The wire format of a HaloPoint, free of padding and of Eigen's layout.
struct WirePoint {
  std::int64_t id;
  double x, y, z;
  std::int32_t owner;
  std::int32_t owner_index;
};
static_assert(sizeof(WirePoint) == 40, "WirePoint must not be padded");

void check_mpi(int code, const char* call) {
  TEXSIM_VERIFY(code == MPI_SUCCESS, "exchange_point_halo: " << call << " failed (" << code << ")");
}

} // namespace

Box3 Box3::expanded(double margin) const {
  Box3 box = *this;
  if (!empty()) {
    box.lo.array() -= margin;
    box.hi.array() += margin;
  }
  return box;
}

Box3 Box3::around(std::span<const Vec3> points) {
  Box3 box;
  for (const auto& p : points) {
    box.lo = box.lo.cwiseMin(p);
    box.hi = box.hi.cwiseMax(p);
  }
  return box;
}

std::vector<HaloPoint> exchange_point_halo(const par::Comm& comm,
                                           std::span<const std::int64_t> owned_ids,
                                           std::span<const Vec3> owned_positions,
                                           const Box3& needed) {
  TEXSIM_VERIFY(owned_ids.size() == owned_positions.size(),
                "exchange_point_halo: " << owned_ids.size() << " ids but "
                                        << owned_positions.size() << " positions");
  const int ranks = comm.size;
  std::array<double, 6> mine{needed.lo.x(), needed.lo.y(), needed.lo.z(),
                             needed.hi.x(), needed.hi.y(), needed.hi.z()};
  std::vector<double> all_boxes(6 * static_cast<std::size_t>(ranks));
  check_mpi(MPI_Allgather(mine.data(), 6, MPI_DOUBLE, all_boxes.data(), 6, MPI_DOUBLE, comm.raw),
            "MPI_Allgather");

  // Bucket the outgoing points by destination (rank order, then owned order).
  std::vector<std::vector<WirePoint>> outgoing(ranks);
  const Box3 own_extent = Box3::around(owned_positions);
  for (int r = 0; r < ranks; ++r) {
    if (r == comm.rank)
      continue;
    Box3 box;
    box.lo = Vec3(all_boxes[6 * r], all_boxes[6 * r + 1], all_boxes[6 * r + 2]);
    box.hi = Vec3(all_boxes[6 * r + 3], all_boxes[6 * r + 4], all_boxes[6 * r + 5]);
    const bool overlaps = !box.empty() && !own_extent.empty() &&
                          (box.lo.array() <= own_extent.hi.array()).all() &&
                          (own_extent.lo.array() <= box.hi.array()).all();
    if (!overlaps)
      continue;
    for (std::size_t i = 0; i < owned_positions.size(); ++i) {
      const Vec3& p = owned_positions[i];
      if (box.contains(p))
        outgoing[r].push_back({owned_ids[i], p.x(), p.y(), p.z(), comm.rank,
                               static_cast<std::int32_t>(i)});
    }
  }

  std::vector<int> send_counts(ranks), send_offsets(ranks), recv_counts(ranks), recv_offsets(ranks);
  std::size_t send_total = 0;
  for (int r = 0; r < ranks; ++r) {
    TEXSIM_VERIFY(outgoing[r].size() < std::size_t(1) << 30,
                  "exchange_point_halo: too many points for one rank (" << outgoing[r].size()
                                                                        << ")");
    send_counts[r] = static_cast<int>(outgoing[r].size());
    send_offsets[r] = static_cast<int>(send_total);
    send_total += outgoing[r].size();
  }
  check_mpi(MPI_Alltoall(send_counts.data(), 1, MPI_INT, recv_counts.data(), 1, MPI_INT, comm.raw),
            "MPI_Alltoall");
  std::size_t recv_total = 0;
  for (int r = 0; r < ranks; ++r) {
    recv_offsets[r] = static_cast<int>(recv_total);
    recv_total += static_cast<std::size_t>(recv_counts[r]);
  }
  TEXSIM_VERIFY(send_total < std::size_t(1) << 31 && recv_total < std::size_t(1) << 31,
                "exchange_point_halo: halo of " << recv_total << " points too large");
  std::vector<WirePoint> send_buffer;
  send_buffer.reserve(send_total);
  for (const auto& bucket : outgoing)
    send_buffer.insert(send_buffer.end(), bucket.begin(), bucket.end());
  std::vector<WirePoint> recv_buffer(recv_total);

  MPI_Datatype wire_type;
  check_mpi(MPI_Type_contiguous(sizeof(WirePoint), MPI_BYTE, &wire_type), "MPI_Type_contiguous");
  check_mpi(MPI_Type_commit(&wire_type), "MPI_Type_commit");
  const int code = MPI_Alltoallv(send_buffer.data(), send_counts.data(), send_offsets.data(),
                                 wire_type, recv_buffer.data(), recv_counts.data(),
                                 recv_offsets.data(), wire_type, comm.raw);
  MPI_Type_free(&wire_type);
  check_mpi(code, "MPI_Alltoallv");

  std::vector<HaloPoint> halo(recv_total);
  for (std::size_t i = 0; i < recv_total; ++i) {
    const WirePoint& w = recv_buffer[i];
    halo[i] = {w.id, Vec3(w.x, w.y, w.z), w.owner, w.owner_index};
  }
  std::sort(halo.begin(), halo.end(),
            [](const HaloPoint& a, const HaloPoint& b) { return a.id < b.id; });
  return halo;
}

} // namespace texsim::geom
