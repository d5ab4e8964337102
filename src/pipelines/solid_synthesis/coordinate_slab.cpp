#include "pipelines/solid_synthesis/coordinate_slab.hpp"

#include "core/error.hpp"
#include "par/record_exchange.hpp"

#include <algorithm>
#include <bit>

namespace texsim::pipelines::solid_synthesis {
namespace {

/// Slabs as thin as the halo: the ring exchange then still finds every halo plane on the next
/// rank.
constexpr int kMinPlanesPerRank = kSlabHalo;

} // namespace

LevelLayout level_layout(int level, int rank, int ranks) {
  const int size = 1 << level;
  const int active = std::min(ranks, size / kMinPlanesPerRank);
  if (active <= 1)
    return {size, 0, size, true, 1};
  if (rank >= active)
    return {size, size, size, false, active};
  const auto bound = [&](int r) { return static_cast<int>(std::int64_t{size} * r / active); };
  return {size, bound(rank), bound(rank + 1), false, active};
}

CoordinateSlab::CoordinateSlab(const LevelLayout& layout)
    : layout_(layout),
      values_(static_cast<std::size_t>(layout.z_end - layout.z_begin + 2 * kSlabHalo) *
              static_cast<std::size_t>(layout.size) * static_cast<std::size_t>(layout.size)) {
  TEXSIM_VERIFY(layout.size > 0 && (layout.size & (layout.size - 1)) == 0,
                "level size must be a power of two, got " << layout.size);
}

std::span<Position> CoordinateSlab::owned() {
  return {values_.data() + kSlabHalo * plane_size(),
          static_cast<std::size_t>(layout_.z_end - layout_.z_begin) * plane_size()};
}

std::span<const Position> CoordinateSlab::owned() const {
  return {values_.data() + kSlabHalo * plane_size(),
          static_cast<std::size_t>(layout_.z_end - layout_.z_begin) * plane_size()};
}

void CoordinateSlab::exchange_halo(const par::Comm& comm) {
  const std::size_t plane = plane_size();
  const int owned_planes = layout_.z_end - layout_.z_begin;
  Position* data = values_.data();
  // Local plane index of global plane z (halo planes included).
  const auto local = [&](int z) {
    return static_cast<std::size_t>(z - layout_.z_begin + kSlabHalo);
  };

  if (layout_.replicated) {
    const int n = layout_.size;
    for (int h = 1; h <= kSlabHalo; ++h) {
      const int below = ((-h) % n + n) % n;
      const int above = (n - 1 + h) % n;
      std::copy_n(data + local(below) * plane, plane, data + local(-h) * plane);
      std::copy_n(data + local(above) * plane, plane, data + local(n - 1 + h) * plane);
    }
    return;
  }
  if (comm.rank >= layout_.ranks)
    return;
  TEXSIM_VERIFY(owned_planes >= kSlabHalo, "slab of " << owned_planes << " planes is thinner "
                                                      << "than the halo");
  const int previous = (comm.rank + layout_.ranks - 1) % layout_.ranks;
  const int next = (comm.rank + 1) % layout_.ranks;
  const int count = static_cast<int>(kSlabHalo * plane * 3);
  static_assert(sizeof(Position) == 3 * sizeof(std::int32_t));
  // Lowest owned planes go to the previous rank's upper halo; highest to the next rank's lower.
  MPI_Sendrecv(data + local(layout_.z_begin) * plane, count, MPI_INT32_T, previous, 31,
               data + local(layout_.z_end) * plane, count, MPI_INT32_T, next, 31, comm.raw,
               MPI_STATUS_IGNORE);
  MPI_Sendrecv(data + local(layout_.z_end - kSlabHalo) * plane, count, MPI_INT32_T, next, 32,
               data + local(layout_.z_begin - kSlabHalo) * plane, count, MPI_INT32_T, previous, 32,
               comm.raw, MPI_STATUS_IGNORE);
}

PlaneRange reported_planes(const par::Comm& comm, const CoordinateSlab& slab, int crop_nz) {
  const LevelLayout& layout = slab.layout();
  if (layout.replicated)
    return comm.is_root() ? PlaneRange{0, crop_nz} : PlaneRange{};
  return {layout.z_begin, std::max(layout.z_begin, std::min(layout.z_end, crop_nz))};
}

CoordinateSlab parent_planes(const par::Comm& comm, const CoordinateSlab& parent,
                             const LevelLayout& child) {
  const LevelLayout& own = parent.layout();
  TEXSIM_VERIFY(child.size == 2 * own.size,
                "a level of " << child.size << " voxels under one of " << own.size);
  // Parent planes [first, last) read by the owned planes of a child layout.
  const auto needed = [](const LevelLayout& c) {
    return c.z_begin < c.z_end ? std::pair{c.z_begin / 2, (c.z_end + 1) / 2} : std::pair{0, 0};
  };
  const auto [first, last] = needed(child);
  CoordinateSlab planes({own.size, first, last, false, comm.size});
  const std::size_t plane = planes.plane_size();
  if (own.replicated) {
    for (int z = first; z < last; ++z)
      std::copy_n(&parent.at(0, 0, z), plane, &planes.at(0, 0, z));
    return planes;
  }
  const int child_level = std::countr_zero(static_cast<unsigned>(child.size));
  std::vector<std::vector<Position>> outgoing(static_cast<std::size_t>(comm.size));
  for (int r = 0; r < comm.size; ++r) {
    const auto [from, to] = needed(level_layout(child_level, r, comm.size));
    for (int z = std::max(from, own.z_begin); z < std::min(to, own.z_end); ++z)
      outgoing[static_cast<std::size_t>(r)].insert(outgoing[static_cast<std::size_t>(r)].end(),
                                                   &parent.at(0, 0, z),
                                                   &parent.at(0, 0, z) + plane);
  }
  // The owners' planes are disjoint and increasing with the rank: they arrive in order.
  const auto received = par::exchange_records(comm, outgoing);
  TEXSIM_VERIFY(received.size() == static_cast<std::size_t>(last - first) * plane,
                "parent planes " << first << " .. " << last - 1 << ": " << received.size()
                                 << " voxels received");
  std::copy(received.begin(), received.end(), planes.owned().begin());
  return planes;
}

} // namespace texsim::pipelines::solid_synthesis
