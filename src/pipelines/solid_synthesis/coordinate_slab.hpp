#pragma once
/// The synthesized volume S of one pyramid level: an exemplar position per voxel, split into
/// z-slabs across ranks with a halo of planes copied from the neighbouring slabs.
///
/// Levels are n^3 with n a power of two and the volume is a 3-torus (the result tiles), so x and
/// y wrap with a mask and the slabs form a ring. A coarse level is split over as many ranks as
/// it has pairs of planes (the rest wait), and the two coarsest (1 and 2 voxels wide) are
/// replicated on every rank; the computation per voxel is the same either way, which is what
/// makes the result the same bytes for any rank count.
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

/// Fractional bits of an exemplar position: positions are kept to 1/256 of a voxel.
inline constexpr int kSubvoxelBits = 8;

/// An exemplar position in fixed point, 2^-kSubvoxelBits voxel units: S[p]. Anisometric synthesis
/// predicts p's position from a neighbour q as S[q] - h A (q - p), rarely a whole voxel; rounding
/// it at every prediction lets half a voxel of error compound over passes and levels until no
/// two neighbours continue one patch (Lefebvre and Hoppe's GPU synthesis keeps the fraction for
/// the same reason). Features and colours are read at the nearest voxel.
struct Position {
  std::int32_t x = 0;
  std::int32_t y = 0;
  std::int32_t z = 0;

  static Position at_voxel(const Coord& c) {
    return {c.x * (1 << kSubvoxelBits), c.y * (1 << kSubvoxelBits), c.z * (1 << kSubvoxelBits)};
  }
  /// The nearest voxel, halves rounded up: floor(x + 1/2).
  Coord voxel() const {
    constexpr std::int32_t half = 1 << (kSubvoxelBits - 1);
    return {(x + half) >> kSubvoxelBits, (y + half) >> kSubvoxelBits, (z + half) >> kSubvoxelBits};
  }
  /// What is left after the nearest voxel: in [-1/2, 1/2) voxel.
  Position fraction() const { return *this - at_voxel(voxel()); }

  friend Position operator+(Position a, Position b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
  friend Position operator-(Position a, Position b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
  friend bool operator==(const Position&, const Position&) = default;
};

/// Which z-planes of a level this rank computes.
struct LevelLayout {
  int size = 1;           ///< n: the level is n^3 voxels
  int z_begin = 0;        ///< first owned plane
  int z_end = 1;          ///< one past the last owned plane
  bool replicated = true; ///< every rank holds (and computes) the whole level
  int ranks = 1;          ///< the ranks holding planes of a split level: 0 .. ranks - 1
};

/// Layout of pyramid level `level` (2^level voxels a side) on `rank` of `ranks`. A level is split
/// over min(ranks, n / kSlabHalo) ranks, evenly, so every slab is at least a halo thick; the
/// other ranks hold no plane of it (z_begin = z_end = n). Only levels of fewer than 2 kSlabHalo
/// planes (1 and 2 voxels wide) are replicated. A child's parent planes may lie on other ranks:
/// parent_planes() fetches them.
LevelLayout level_layout(int level, int rank, int ranks);

/// Planes of halo on each side: the correction reads voxels up to 2 planes away.
inline constexpr int kSlabHalo = 2;

class CoordinateSlab {
public:
  explicit CoordinateSlab(const LevelLayout& layout);

  const LevelLayout& layout() const { return layout_; }
  int size() const { return layout_.size; }

  /// Voxel (i, j, k): i and j any integers (periodic), k within the owned planes +- kSlabHalo.
  Position& at(int i, int j, int k) { return values_[index(i, j, k)]; }
  const Position& at(int i, int j, int k) const { return values_[index(i, j, k)]; }
  /// The exemplar voxel whose colour voxel (i, j, k) shows.
  Coord voxel(int i, int j, int k) const { return at(i, j, k).voxel(); }

  /// Voxels in one plane: n^2.
  std::size_t plane_size() const {
    return static_cast<std::size_t>(layout_.size) * static_cast<std::size_t>(layout_.size);
  }

  /// The owned planes, x fastest (what a checkpoint or the output stores).
  std::span<Position> owned();
  std::span<const Position> owned() const;

  /// Fills the halo planes from the neighbouring slabs (ring over the ranks holding planes), or
  /// from this slab's own planes when the level is replicated. Collective when the level is split
  /// (a rank holding no plane returns at once).
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

  LevelLayout layout_;
  std::vector<Position> values_;
};

/// Planes [begin, end) of a level's z-crop [0, crop_nz) that this rank reports (outputs, sums
/// over the result): its owned planes, or on a replicated level all of them on rank 0 and none
/// elsewhere, so every plane is reported once.
struct PlaneRange {
  int begin = 0;
  int end = 0;
};
PlaneRange reported_planes(const par::Comm& comm, const CoordinateSlab& slab, int crop_nz);

/// The planes of `parent` that the child level laid out by `child` (this rank's layout of the
/// level below `parent`) reads when it is made: planes z / 2 of its owned planes z, fetched from
/// the ranks that own them, as the owned planes of a slab of the parent's size (no halo). Empty
/// when this rank holds no child plane. Collective.
CoordinateSlab parent_planes(const par::Comm& comm, const CoordinateSlab& parent,
                             const LevelLayout& child);

} // namespace texsim::pipelines::solid_synthesis
