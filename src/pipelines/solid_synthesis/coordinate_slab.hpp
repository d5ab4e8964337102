#pragma once
/// The synthesized volume S of one pyramid level: an exemplar coordinate per voxel, split into
/// z-slabs across ranks with a halo of planes copied from the neighbouring slabs.
///
/// Levels are n^3 with n a power of two and the volume is a 3-torus (the result tiles), so x and
/// y wrap with a mask and the slabs form a ring. Coarse levels, too thin to split, are replicated
/// on every rank; the computation per voxel is the same either way, which is what makes the
/// result the same bytes for any rank count.
#include "par/comm.hpp"

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

namespace texsim::pipelines::solid_synthesis {

/// An exemplar voxel coordinate (or an offset between two).
struct Coord {
  std::int32_t x = 0;
  std::int32_t y = 0;
  std::int32_t z = 0;
  friend Coord operator+(Coord a, Coord b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
  friend Coord operator-(Coord a, Coord b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
  friend bool operator==(const Coord&, const Coord&) = default;
};

/// Which z-planes of a level this rank computes.
struct LevelLayout {
  int size = 1;           ///< n: the level is n^3 voxels
  int z_begin = 0;        ///< first owned plane
  int z_end = 1;          ///< one past the last owned plane
  bool replicated = true; ///< every rank holds (and computes) the whole level
};

/// Layout of pyramid level `level` (2^level voxels a side) on `rank` of `ranks`. The first level
/// at least kSlabHalo (2) planes per rank thick is split evenly; every finer level doubles those
/// bounds, so a child plane's parent is always in the rank's own parent slab. Coarser levels are
/// replicated.
LevelLayout level_layout(int level, int rank, int ranks);

/// Planes of halo on each side: the correction reads voxels up to 2 planes away.
inline constexpr int kSlabHalo = 2;

class CoordinateSlab {
public:
  explicit CoordinateSlab(const LevelLayout& layout);

  const LevelLayout& layout() const { return layout_; }
  int size() const { return layout_.size; }

  /// Voxel (i, j, k): i and j any integers (periodic), k within the owned planes +- kSlabHalo.
  Coord& at(int i, int j, int k) { return values_[index(i, j, k)]; }
  const Coord& at(int i, int j, int k) const { return values_[index(i, j, k)]; }

  /// The owned planes, x fastest (what a checkpoint or the output stores).
  std::span<Coord> owned();
  std::span<const Coord> owned() const;

  /// Fills the halo planes from the neighbouring slabs (ring over ranks), or from this slab's own
  /// planes when the level is replicated. Collective when the level is split.
  void exchange_halo(const par::Comm& comm);

private:
  std::size_t index(int i, int j, int k) const {
    const int mask = layout_.size - 1;
    return static_cast<std::size_t>(i & mask) +
           static_cast<std::size_t>(layout_.size) *
               (static_cast<std::size_t>(j & mask) +
                static_cast<std::size_t>(layout_.size) *
                    static_cast<std::size_t>(k - layout_.z_begin + kSlabHalo));
  }
  std::size_t plane_size() const {
    return static_cast<std::size_t>(layout_.size) * static_cast<std::size_t>(layout_.size);
  }

  LevelLayout layout_;
  std::vector<Coord> values_;
};

} // namespace texsim::pipelines::solid_synthesis
