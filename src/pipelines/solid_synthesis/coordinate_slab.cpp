#include "pipelines/solid_synthesis/coordinate_slab.hpp"

#include "core/error.hpp"

#include <algorithm>

namespace texsim::pipelines::solid_synthesis {
namespace {

/// Slabs as thin as the halo: the ring exchange then still finds every halo plane on the next
/// rank, and a child's parent plane lies in the rank's own slab by the doubling of the bounds.
constexpr int kMinPlanesPerRank = kSlabHalo;

} // namespace

LevelLayout level_layout(int level, int rank, int ranks) {
  const int size = 1 << level;
  if (ranks == 1 || size < kMinPlanesPerRank * ranks)
    return {size, 0, size, true};
  int first_split = 0;
  while ((1 << first_split) < kMinPlanesPerRank * ranks)
    ++first_split;
  const auto bound = [&](int r) {
    const std::int64_t coarse = (std::int64_t{r} << first_split) / ranks;
    return static_cast<int>(coarse << (level - first_split));
  };
  return {size, bound(rank), bound(rank + 1), false};
}

CoordinateSlab::CoordinateSlab(const LevelLayout& layout)
    : layout_(layout),
      values_(static_cast<std::size_t>(layout.z_end - layout.z_begin + 2 * kSlabHalo) *
              static_cast<std::size_t>(layout.size) * static_cast<std::size_t>(layout.size)) {
  TEXSIM_VERIFY(layout.size > 0 && (layout.size & (layout.size - 1)) == 0,
                "level size must be a power of two, got " << layout.size);
}

std::span<Coord> CoordinateSlab::owned() {
  return {values_.data() + kSlabHalo * plane_size(),
          static_cast<std::size_t>(layout_.z_end - layout_.z_begin) * plane_size()};
}

std::span<const Coord> CoordinateSlab::owned() const {
  return {values_.data() + kSlabHalo * plane_size(),
          static_cast<std::size_t>(layout_.z_end - layout_.z_begin) * plane_size()};
}

void CoordinateSlab::exchange_halo(const par::Comm& comm) {
  const std::size_t plane = plane_size();
  const int owned_planes = layout_.z_end - layout_.z_begin;
  Coord* data = values_.data();
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
  TEXSIM_VERIFY(owned_planes >= kSlabHalo, "slab of " << owned_planes << " planes is thinner "
                                                      << "than the halo");
  const int previous = (comm.rank + comm.size - 1) % comm.size;
  const int next = (comm.rank + 1) % comm.size;
  const int count = static_cast<int>(kSlabHalo * plane * 3);
  static_assert(sizeof(Coord) == 3 * sizeof(std::int32_t));
  // Lowest owned planes go to the previous rank's upper halo; highest to the next rank's lower.
  MPI_Sendrecv(data + local(layout_.z_begin) * plane, count, MPI_INT32_T, previous, 31,
               data + local(layout_.z_end) * plane, count, MPI_INT32_T, next, 31, comm.raw,
               MPI_STATUS_IGNORE);
  MPI_Sendrecv(data + local(layout_.z_end - kSlabHalo) * plane, count, MPI_INT32_T, next, 32,
               data + local(layout_.z_begin - kSlabHalo) * plane, count, MPI_INT32_T, previous, 32,
               comm.raw, MPI_STATUS_IGNORE);
}

} // namespace texsim::pipelines::solid_synthesis
