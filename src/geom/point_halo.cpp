#include "geom/point_halo.hpp"

#include "core/error.hpp"

#include <mpi.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <unordered_map>

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

// Finds the boxes that may contain a point: boxes listed under the cells of a uniform grid
// (cell edge: the median box extent) that they overlap; boxes spanning many cells, and all boxes
// when there are few, are checked for every point.
class BoxIndex {
public:
  BoxIndex(const std::vector<Box3>& boxes, const Box3& region) {
    if (boxes.size() <= 16 || region.empty()) {
      for (std::size_t b = 0; b < boxes.size(); ++b)
        everywhere_.push_back(b);
      return;
    }
    std::vector<double> extents(boxes.size());
    for (std::size_t b = 0; b < boxes.size(); ++b)
      extents[b] = (boxes[b].hi - boxes[b].lo).maxCoeff();
    std::nth_element(extents.begin(), extents.begin() + extents.size() / 2, extents.end());
    origin_ = region.lo;
    cell_ = std::max({extents[extents.size() / 2], (region.hi - region.lo).maxCoeff() / 1e6,
                      std::numeric_limits<double>::min()});
    for (int axis = 0; axis < 3; ++axis)
      cells_[axis] = cell_index(region.hi[axis], axis) + 1;
    std::vector<std::pair<std::uint64_t, std::uint32_t>> entries;
    for (std::size_t b = 0; b < boxes.size(); ++b) {
      std::array<std::int64_t, 3> lo, hi;
      std::int64_t span = 1;
      for (int axis = 0; axis < 3; ++axis) {
        lo[axis] = cell_index(boxes[b].lo[axis], axis);
        hi[axis] = cell_index(boxes[b].hi[axis], axis);
        span *= hi[axis] - lo[axis] + 1;
      }
      if (span > 64) {
        everywhere_.push_back(b);
        continue;
      }
      for (std::int64_t z = lo[2]; z <= hi[2]; ++z)
        for (std::int64_t y = lo[1]; y <= hi[1]; ++y)
          for (std::int64_t x = lo[0]; x <= hi[0]; ++x)
            entries.emplace_back(key(x, y, z), static_cast<std::uint32_t>(b));
    }
    std::sort(entries.begin(), entries.end());
    keys_.reserve(entries.size());
    listed_.reserve(entries.size());
    for (const auto& [k, b] : entries) {
      keys_.push_back(k);
      listed_.push_back(b);
    }
  }

  /// Calls visit(box index) for every box that may contain p (some more than once is impossible:
  /// each box is listed once per cell).
  template <class Visit> void for_each_candidate(const Vec3& p, Visit&& visit) const {
    for (const std::size_t b : everywhere_)
      visit(b);
    if (keys_.empty())
      return;
    const std::uint64_t k = key(cell_index(p.x(), 0), cell_index(p.y(), 1), cell_index(p.z(), 2));
    const auto first = std::lower_bound(keys_.begin(), keys_.end(), k);
    for (auto it = first; it != keys_.end() && *it == k; ++it)
      visit(listed_[it - keys_.begin()]);
  }

private:
  // Cell of coordinate v along axis, clamped to the region's cells.
  std::int64_t cell_index(double v, int axis) const {
    const double f = std::floor((v - origin_[axis]) / cell_);
    return static_cast<std::int64_t>(std::clamp(f, 0.0, double(cells_[axis] - 1)));
  }
  static std::uint64_t key(std::int64_t x, std::int64_t y, std::int64_t z) {
    return std::uint64_t(x) | std::uint64_t(y) << 21 | std::uint64_t(z) << 42;
  }

  Vec3 origin_ = Vec3::Zero();
  double cell_ = 1.0;
  std::array<std::int64_t, 3> cells_{1 << 20, 1 << 20, 1 << 20};
  std::vector<std::size_t> everywhere_;
  std::vector<std::uint64_t> keys_;
  std::vector<std::uint32_t> listed_;
};

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

std::vector<Box3> covering_boxes(std::span<const Vec3> positions, double cell, double reach) {
  TEXSIM_VERIFY(cell > 0.0 && reach >= 0.0, "covering_boxes: cell "
                                                << cell << " must be positive, reach " << reach
                                                << " not negative");
  const Box3 extent = Box3::around(positions);
  if (extent.empty())
    return {};
  // At most 2^20 cells per axis so that a cell's key fits in 63 bits.
  const double size = std::max(cell, (extent.hi - extent.lo).maxCoeff() / double(1 << 20));
  std::unordered_map<std::uint64_t, std::size_t> box_of_cell;
  std::vector<std::uint64_t> keys;
  std::vector<Box3> boxes;
  for (const Vec3& p : positions) {
    std::uint64_t key = 0;
    for (int axis = 0; axis < 3; ++axis)
      key |= static_cast<std::uint64_t>((p[axis] - extent.lo[axis]) / size) << (21 * axis);
    const auto [it, inserted] = box_of_cell.try_emplace(key, boxes.size());
    if (inserted) {
      boxes.emplace_back();
      keys.push_back(key);
    }
    Box3& box = boxes[it->second];
    box.lo = box.lo.cwiseMin(p);
    box.hi = box.hi.cwiseMax(p);
  }
  // In cell order, so the result does not depend on the order of the points.
  std::vector<std::size_t> order(boxes.size());
  for (std::size_t b = 0; b < order.size(); ++b)
    order[b] = b;
  std::sort(order.begin(), order.end(),
            [&](std::size_t a, std::size_t b) { return keys[a] < keys[b]; });
  std::vector<Box3> result;
  result.reserve(boxes.size());
  for (const std::size_t b : order)
    result.push_back(boxes[b].expanded(reach));
  return result;
}

std::vector<char> inside_boxes(std::span<const Vec3> points, std::span<const Box3> boxes) {
  const std::vector<Box3> listed(boxes.begin(), boxes.end());
  const BoxIndex index(listed, Box3::around(points));
  std::vector<char> inside(points.size(), 0);
  for (std::size_t i = 0; i < points.size(); ++i)
    index.for_each_candidate(
        points[i], [&](std::size_t b) { inside[i] = inside[i] || listed[b].contains(points[i]); });
  return inside;
}

std::vector<HaloPoint> exchange_point_halo(const par::Comm& comm,
                                           std::span<const std::int64_t> owned_ids,
                                           std::span<const Vec3> owned_positions,
                                           const Box3& needed) {
  if (needed.empty())
    return exchange_point_halo(comm, owned_ids, owned_positions, std::span<const Box3>());
  return exchange_point_halo(comm, owned_ids, owned_positions, std::span<const Box3>(&needed, 1));
}

std::vector<HaloPoint> exchange_point_halo(const par::Comm& comm,
                                           std::span<const std::int64_t> owned_ids,
                                           std::span<const Vec3> owned_positions,
                                           std::span<const Box3> needed) {
  TEXSIM_VERIFY(owned_ids.size() == owned_positions.size(),
                "exchange_point_halo: " << owned_ids.size() << " ids but " << owned_positions.size()
                                        << " positions");
  const int ranks = comm.size;
  TEXSIM_VERIFY(needed.size() < std::size_t(1) << 28,
                "exchange_point_halo: too many boxes (" << needed.size() << ")");
  // Allgather the boxes: counts, then 6 doubles per box.
  const int my_boxes = static_cast<int>(needed.size());
  std::vector<int> box_counts(ranks), box_offsets(ranks);
  check_mpi(MPI_Allgather(&my_boxes, 1, MPI_INT, box_counts.data(), 1, MPI_INT, comm.raw),
            "MPI_Allgather");
  std::size_t all_count = 0;
  for (int r = 0; r < ranks; ++r) {
    box_offsets[r] = static_cast<int>(6 * all_count);
    all_count += static_cast<std::size_t>(box_counts[r]);
    box_counts[r] *= 6;
  }
  TEXSIM_VERIFY(6 * all_count < std::size_t(1) << 31,
                "exchange_point_halo: too many boxes in all (" << all_count << ")");
  std::vector<double> mine(6 * needed.size());
  for (std::size_t b = 0; b < needed.size(); ++b)
    for (int axis = 0; axis < 3; ++axis) {
      mine[6 * b + axis] = needed[b].lo[axis];
      mine[6 * b + 3 + axis] = needed[b].hi[axis];
    }
  std::vector<double> all_boxes(6 * all_count);
  check_mpi(MPI_Allgatherv(mine.data(), 6 * my_boxes, MPI_DOUBLE, all_boxes.data(),
                           box_counts.data(), box_offsets.data(), MPI_DOUBLE, comm.raw),
            "MPI_Allgatherv");

  // The other ranks' boxes that can hold one of this rank's points.
  const Box3 own_extent = Box3::around(owned_positions);
  std::vector<Box3> boxes;
  std::vector<int> box_rank;
  for (int r = 0; r < ranks; ++r) {
    if (r == comm.rank)
      continue;
    for (int k = 0; k < box_counts[r] / 6; ++k) {
      const double* v = all_boxes.data() + box_offsets[r] + 6 * k;
      Box3 box;
      box.lo = Vec3(v[0], v[1], v[2]);
      box.hi = Vec3(v[3], v[4], v[5]);
      const bool overlaps = !box.empty() && !own_extent.empty() &&
                            (box.lo.array() <= own_extent.hi.array()).all() &&
                            (own_extent.lo.array() <= box.hi.array()).all();
      if (overlaps) {
        boxes.push_back(box);
        box_rank.push_back(r);
      }
    }
  }
  const BoxIndex index(boxes, own_extent);

  // Bucket the outgoing points by destination (rank order, then owned order); a point goes to a
  // rank once however many of its boxes hold it.
  std::vector<std::vector<WirePoint>> outgoing(ranks);
  std::vector<std::int64_t> last_sent(ranks, -1);
  for (std::size_t i = 0; i < owned_positions.size(); ++i) {
    const Vec3& p = owned_positions[i];
    index.for_each_candidate(p, [&](std::size_t b) {
      const int r = box_rank[b];
      if (last_sent[r] != std::int64_t(i) && boxes[b].contains(p)) {
        last_sent[r] = std::int64_t(i);
        outgoing[r].push_back(
            {owned_ids[i], p.x(), p.y(), p.z(), comm.rank, static_cast<std::int32_t>(i)});
      }
    });
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
