#include "pipelines/solid_synthesis/pyramid_synthesizer.hpp"

#include "core/error.hpp"
#include "core/rng.hpp"
#include "par/node_shared_array.hpp"
#include "pipelines/solid_synthesis/correction_stencil.hpp"

#include <Eigen/Core>
#include <mpi.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <optional>
#include <span>
#include <utility>

namespace texsim::pipelines::solid_synthesis {
namespace {

/// Stream of the jitter hash H(p) of eq. (2).
constexpr std::uint32_t kJitterStream = 0x5353;

int wrap(int v, int n) {
  const int m = v % n;
  return m < 0 ? m + n : m;
}

/// Wrapping of one exemplar axis by table lookup: the correction computes hundreds of wrapped
/// coordinates per voxel, and integer division would dominate its cost. Offsets beyond the
/// table's margin (large anisometric scales) fall back to the modulo.
class AxisWrap {
public:
  AxisWrap(int n, std::int64_t stride)
      : n_(n), margin_(16 * n + 256), stride_(stride), table_(2 * margin_ + n) {
    for (int v = -margin_; v < n + margin_; ++v)
      table_[v + margin_] = wrap(v, n) * stride;
  }
  std::int64_t operator()(int v) const {
    const int at = v + margin_;
    return at >= 0 && at < static_cast<int>(table_.size()) ? table_[at] : wrap(v, n_) * stride_;
  }

private:
  int n_;
  int margin_;
  std::int64_t stride_;
  std::vector<std::int64_t> table_;
};

/// Features and similarity sets of one stack level, with the lookups the correction needs.
class ExemplarLevelView {
public:
  /// Collective over `comm` (the candidates' coordinates are held once per node).
  ExemplarLevelView(const par::Comm& comm, const vol::ChannelGrid& features,
                    const SimilaritySets& sets)
      : features_(cache_line_aligned(features.data(), feature_storage_)), k_(sets.k),
        channels_(features.channels()), wrap_x_(features.dims().nx, 1),
        wrap_y_(features.dims().ny, features.dims().nx),
        wrap_z_(features.dims().nz, std::int64_t{features.dims().nx} * features.dims().ny),
        candidates_(par::NodeSharedArray<Coord>::filled(
            par::NodeLayout::make(comm), sets.candidates.size(),
            [&](std::span<Coord> all, std::size_t begin, std::size_t end) {
              const vol::Dims dims = features.dims();
              for (std::size_t c = begin; c < end; ++c) {
                const std::int64_t v = sets.candidates[c];
                all[c] = {static_cast<std::int32_t>(v % dims.nx),
                          static_cast<std::int32_t>((v / dims.nx) % dims.ny),
                          static_cast<std::int32_t>(v / (std::int64_t{dims.nx} * dims.ny))};
              }
            })) {}

  int channels() const { return channels_; }
  int k() const { return k_; }

  /// Storage index of the exemplar voxel at coordinate c, wrapped.
  std::int64_t index(const Coord& c) const { return wrap_x_(c.x) + wrap_y_(c.y) + wrap_z_(c.z); }
  const float* feature(const Coord& c) const { return features_ + index(c) * channels_; }
  /// C_1..k of the exemplar voxel at coordinate c.
  const Coord* candidates(const Coord& c) const {
    return candidates_.data() + static_cast<std::size_t>(index(c) * k_);
  }

private:
  /// `values` themselves if they start on a cache-line boundary (node-shared features do),
  /// otherwise a copy inside `storage` that does: a voxel of 8 channels then fills half a line,
  /// where at the allocator's 16-byte alignment every other voxel straddles two lines, two cache
  /// misses instead of one.
  static const float* cache_line_aligned(std::span<const float> values,
                                         std::vector<float>& storage) {
    constexpr std::size_t kLineFloats = 64 / sizeof(float);
    if (reinterpret_cast<std::uintptr_t>(values.data()) % 64 == 0)
      return values.data();
    storage.resize(values.size() + kLineFloats);
    const std::size_t misalignment =
        reinterpret_cast<std::uintptr_t>(storage.data()) % 64 / sizeof(float);
    float* start = storage.data() + (kLineFloats - misalignment) % kLineFloats;
    std::copy(values.begin(), values.end(), start);
    return start;
  }

  std::vector<float> feature_storage_; // before features_, which may point into it
  const float* features_;
  int k_;
  int channels_;
  AxisWrap wrap_x_, wrap_y_, wrap_z_;
  par::NodeSharedArray<Coord> candidates_;
};

/// Whether two matrices hold the same bits (a stencil is a pure function of them).
bool same_bits(const Eigen::Matrix3f& a, const Eigen::Matrix3f& b) {
  return std::memcmp(a.data(), b.data(), sizeof(float) * 9) == 0;
}

/// The stencil of the last voxel a thread corrected, reused while A, A^-1 and the A_q of the
/// voxels it reads keep the same bits (constant fields, the inside of a zigzag band):
/// make_stencil is a pure function of them.
class StencilCache {
public:
  StencilCache(int h, const LevelJacobians& jacobians) : h_(h), jacobians_(jacobians) {}

  const CorrectionStencil& get(int i, int j, int k) {
    const Eigen::Matrix3f& jacobian = jacobians_.a(i, j, k);
    const Eigen::Matrix3f& inverse_jacobian = jacobians_.a_inverse(i, j, k);
    if (valid_ && same_bits(jacobian, jacobian_) &&
        same_bits(inverse_jacobian, inverse_jacobian_) && same_neighbours(i, j, k))
      return stencil_;
    stencil_ = make_stencil(
        h_, jacobian, inverse_jacobian,
        [&](const Coord& offset) -> const Eigen::Matrix3f& { return neighbour(i, j, k, offset); });
    jacobian_ = jacobian;
    inverse_jacobian_ = inverse_jacobian;
    for (int d = 0; d < kDiagonalCount; ++d)
      for (int m = 0; m < kSubNeighbourCount; ++m)
        neighbours_[d][m] = neighbour(i, j, k, stencil_.sample[d][m]);
    valid_ = true;
    return stencil_;
  }

private:
  const Eigen::Matrix3f& neighbour(int i, int j, int k, const Coord& offset) const {
    return jacobians_.a_periodic(i + offset.x, j + offset.y, k + offset.z);
  }
  /// With the same A^-1 the stencil reads the same offsets; are their Jacobians the same too?
  bool same_neighbours(int i, int j, int k) const {
    for (int d = 0; d < kDiagonalCount; ++d)
      for (int m = 0; m < kSubNeighbourCount; ++m)
        if (!same_bits(neighbour(i, j, k, stencil_.sample[d][m]), neighbours_[d][m]))
          return false;
    return true;
  }

  int h_;
  const LevelJacobians& jacobians_;
  bool valid_ = false;
  Eigen::Matrix3f jacobian_, inverse_jacobian_;
  std::array<std::array<Eigen::Matrix3f, kSubNeighbourCount>, kDiagonalCount> neighbours_;
  CorrectionStencil stencil_;
};

/// Whether every A and A^-1 of `jacobians` has the bits of the first.
bool same_everywhere(const LevelJacobians& jacobians) {
  for (std::size_t v = 0; v < jacobians.jacobian.size(); ++v)
    if (!same_bits(jacobians.jacobian[v], jacobians.jacobian.front()) ||
        !same_bits(jacobians.inverse[v], jacobians.inverse.front()))
      return false;
  return true;
}

/// Per-thread buffers of best_match.
struct MatchScratch {
  explicit MatchScratch(const ExemplarLevelView& exemplar)
      : neighbourhood(kDiagonalCount * exemplar.channels()),
        candidates(kDiagonalCount * exemplar.k()),
        reads(kDiagonalCount * std::max(kSubNeighbourCount, kDiagonalCount * exemplar.k())) {}

  std::vector<float> neighbourhood; ///< N_S(p): 8 averages of `channels` floats
  std::vector<Position> candidates; ///< the 8k candidates, direction-major
  std::vector<const float*> reads;  ///< feature pointers of one phase
};

/// The best of the 8k candidates for voxel p: eqs. (3)-(4) (or (6)-(7)) against N_E(u).
///
/// A voxel reads about 200 scattered exemplar voxels, mostly cache misses once the exemplar
/// outgrows the caches (anisometric results are less coherent, so neighbouring voxels share
/// fewer of them). Each phase therefore first computes its addresses and prefetches them all, so
/// the misses overlap instead of stalling one candidate at a time; the arithmetic and its order
/// are those of the plain loops.
std::pair<Position, double> best_match(const CoordinateSlab& slab, int i, int j, int k,
                                       const CorrectionStencil& stencil,
                                       const ExemplarLevelView& exemplar, float incoherent_scale,
                                       MatchScratch& scratch) {
  const int d = exemplar.channels();
  const int n_candidates = kDiagonalCount * exemplar.k();
  const float** reads = scratch.reads.data();

  const Coord* similarity_sets[kDiagonalCount];
  // A candidate keeps the fraction of the position it was proposed from: C_1 then continues the
  // neighbour's patch exactly.
  Position fractions[kDiagonalCount];
  for (int dir = 0; dir < kDiagonalCount; ++dir) {
    const Coord& source = stencil.source[dir];
    const Position& proposer = slab.at(i + source.x, j + source.y, k + source.z);
    similarity_sets[dir] = exemplar.candidates(proposer.voxel());
    fractions[dir] = proposer.fraction();
    __builtin_prefetch(similarity_sets[dir]);
    __builtin_prefetch(similarity_sets[dir] + exemplar.k() - 1);
  }
  for (int dir = 0; dir < kDiagonalCount; ++dir)
    for (int m = 0; m < kSubNeighbourCount; ++m) {
      const Coord& offset = stencil.sample[dir][m];
      const Position at =
          slab.at(i + offset.x, j + offset.y, k + offset.z) + stencil.sample_shift[dir][m];
      const float* f = exemplar.feature(at.voxel());
      __builtin_prefetch(f);
      reads[dir * kSubNeighbourCount + m] = f;
    }
  Position* candidates = scratch.candidates.data();
  for (int dir = 0; dir < kDiagonalCount; ++dir) {
    const Position shift = fractions[dir] - stencil.source_shift[dir];
    for (int n = 0; n < exemplar.k(); ++n)
      candidates[dir * exemplar.k() + n] = Position::at_voxel(similarity_sets[dir][n]) + shift;
  }

  float* neighbourhood = scratch.neighbourhood.data();
  for (int dir = 0; dir < kDiagonalCount; ++dir) {
    float* average = neighbourhood + dir * d;
    for (int c = 0; c < d; ++c)
      average[c] = 0.0f;
    for (int m = 0; m < kSubNeighbourCount; ++m) {
      const float* f = reads[dir * kSubNeighbourCount + m];
      for (int c = 0; c < d; ++c)
        average[c] += f[c];
    }
    for (int c = 0; c < d; ++c)
      average[c] *= 1.0f / kSubNeighbourCount;
  }

  for (int n = 0; n < n_candidates; ++n) {
    const Coord voxel = candidates[n].voxel();
    for (int e = 0; e < kDiagonalCount; ++e) {
      const float* f = exemplar.feature(voxel + stencil.exemplar_offset[e]);
      __builtin_prefetch(f);
      reads[n * kDiagonalCount + e] = f;
    }
  }
  Position best = slab.at(i, j, k);
  float best_distance = std::numeric_limits<float>::infinity();
  for (int n = 0; n < n_candidates; ++n) {
    // The first entry of a similarity set continues that neighbour's patch.
    const float scale = n % exemplar.k() == 0 ? 1.0f : incoherent_scale;
    float distance = 0.0f;
    for (int e = 0; e < kDiagonalCount && distance * scale < best_distance; ++e) {
      const float* f = reads[n * kDiagonalCount + e];
      const float* target = neighbourhood + e * d;
      for (int c = 0; c < d; ++c) {
        const float diff = f[c] - target[c];
        distance += diff * diff;
      }
    }
    distance *= scale;
    if (distance < best_distance) {
      best_distance = distance;
      best = candidates[n];
    }
  }
  return {best, best_distance};
}

} // namespace

int level_of(const CoordinateSlab& slab) {
  int level = 0;
  while ((1 << level) < slab.size())
    ++level;
  return level;
}

PyramidSynthesizer::PyramidSynthesizer(const par::Comm& comm, SynthesisExemplar exemplar,
                                       SynthesisOptions options, const AxesField* field)
    : comm_(comm), exemplar_(std::move(exemplar)), options_(options), field_(field) {
  TEXSIM_VERIFY(!exemplar_.features.empty() && exemplar_.features.size() == exemplar_.sets.size(),
                "one similarity-set slot per stack level expected");
  TEXSIM_VERIFY(options_.levels >= 0 && options_.levels < 16,
                "pyramid levels out of range: " << options_.levels);
}

int PyramidSynthesizer::stack_level(int level) const {
  const int s = options_.levels - level;
  return std::min(s, static_cast<int>(exemplar_.features.size()) - 1);
}

Position PyramidSynthesizer::wrapped(const Position& c) const {
  // Into [-1/2, n - 1/2) voxels, so that the nearest voxel lies inside the exemplar.
  constexpr int half = 1 << (kSubvoxelBits - 1);
  const auto axis = [](int v, int n) { return wrap(v + half, n << kSubvoxelBits) - half; };
  return {axis(c.x, exemplar_.dims.nx), axis(c.y, exemplar_.dims.ny), axis(c.z, exemplar_.dims.nz)};
}

CoordinateSlab PyramidSynthesizer::first_level(LevelStats& stats) const {
  CoordinateSlab slab(level_layout(0, comm_.rank, comm_.size));
  slab.at(0, 0, 0) = Position{};
  jitter(slab, 0);
  correct(slab, 0, level_jacobians(slab.layout()), stats);
  return slab;
}

std::optional<CoordinateSlab> PyramidSynthesizer::next_level(const CoordinateSlab& parent,
                                                             LevelStats& stats,
                                                             const StopCheck& stop) const {
  const int level = level_of(parent) + 1;
  TEXSIM_VERIFY(level <= options_.levels, "no level after the finest");
  const LevelLayout layout = level_layout(level, comm_.rank, comm_.size);
  CoordinateSlab slab(layout);
  const int n = layout.size;
  const int h = spacing(level);
  const std::optional<LevelJacobians> jacobians = level_jacobians(layout);
  const auto isometric_children = child_offsets(h, Eigen::Matrix3f::Identity());
  const CoordinateSlab parents = parent_planes(comm_, parent, layout);

#pragma omp parallel for schedule(static)
  for (int k = layout.z_begin; k < layout.z_end; ++k)
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) {
        const int child = (i & 1) + 2 * (j & 1) + 4 * (k & 1);
        const Position offset =
            jacobians ? child_offsets(h, jacobians->a(i, j, k))[child] : isometric_children[child];
        slab.at(i, j, k) = wrapped(parents.at(i >> 1, j >> 1, k >> 1) + offset);
      }
  jitter(slab, level);
  if (!correct(slab, level, jacobians, stats, stop))
    return std::nullopt;
  return slab;
}

std::optional<LevelJacobians> PyramidSynthesizer::level_jacobians(const LevelLayout& layout) const {
  if (!field_)
    return std::nullopt;
  // The halo planes too: a stencil reads A at the voxels it predicts from.
  const int halo = layout.z_begin < layout.z_end ? kSlabHalo : 0;
  return sample_level(*field_, layout.size, layout.z_begin - halo, layout.z_end + halo,
                      1 << options_.levels);
}

void PyramidSynthesizer::jitter(CoordinateSlab& slab, int level) const {
  const CounterRng hash(options_.seed, kJitterStream);
  const LevelLayout& layout = slab.layout();
  const int n = layout.size;
  const double amplitude =
      spacing(level) * (level == options_.levels ? options_.finest_jitter : options_.jitter);
#pragma omp parallel for schedule(static)
  for (int k = layout.z_begin; k < layout.z_end; ++k)
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) {
        const std::uint64_t id =
            std::uint64_t(i) + std::uint64_t(n) * (std::uint64_t(j) + std::uint64_t(n) * k);
        const auto offset = [&](int axis) {
          return static_cast<std::int32_t>(
              std::floor(amplitude * hash.uniform(-1.0, 1.0, id, level, axis) + 0.5));
        };
        slab.at(i, j, k) =
            wrapped(slab.at(i, j, k) + Position::at_voxel(Coord{offset(0), offset(1), offset(2)}));
      }
}

/// Fixed-point resolution of the pass sums: 2^-20 of a squared appearance distance per voxel, far
/// below what a pass changes, and 2^63 leaves room for 2^43 units, e.g. 10^4 per voxel on 2^30
/// voxels.
constexpr int kFixedBits = 20;

bool PyramidSynthesizer::correct(CoordinateSlab& slab, int level,
                                 const std::optional<LevelJacobians>& jacobians, LevelStats& stats,
                                 const StopCheck& stop) const {
  const int s = stack_level(level);
  const int h = spacing(level);
  stats = LevelStats{};
  stats.level = level;
  stats.spacing = h;
  stats.stack_level = s;
  const SimilaritySets* sets = exemplar_.sets[s];
  if (!sets || options_.correction_passes == 0)
    return true;
  stats.corrected = true;
  const ExemplarLevelView exemplar(comm_, *exemplar_.features[s], *sets);
  const LevelLayout& layout = slab.layout();
  const int n = layout.size;
  // One stencil for the level when A is the same everywhere this rank reads (isometric, slant):
  // the mean of equal Jacobians is that Jacobian, so the per-voxel stencil would have its bits.
  const bool uniform = !jacobians || same_everywhere(*jacobians);
  const CorrectionStencil level_stencil =
      jacobians && uniform && !jacobians->jacobian.empty()
          ? make_stencil(h, jacobians->jacobian.front(), jacobians->inverse.front())
          : make_stencil(h, Eigen::Matrix3f::Identity(), Eigen::Matrix3f::Identity());
  const auto incoherent_scale = static_cast<float>(1.0 + options_.coherence);

  // One class of the parity lattice: voxels (2a + cx, 2b + cy, 2c + cz); smaller levels have
  // fewer than 2 voxels along an axis, and then classes with c = 1 are empty.
  const int half = std::max(1, n / 2);
  const int planes = layout.z_end - layout.z_begin;
  std::vector<Position> updates(static_cast<std::size_t>(half) * half *
                                std::max(1, (planes + 1) / 2));
  // Replicated levels are computed in full on every rank: count them once.
  const bool counted = !layout.replicated || comm_.rank == 0;
  double distance_sum = 0.0;
  std::int64_t previous_fixed = 0;
  for (int pass = 0; pass < options_.correction_passes; ++pass) {
    double pass_sum = 0.0;
    std::int64_t pass_fixed = 0; // distances in units of 2^-kFixedBits: an exact, ordered-free sum
    for (int subpass = 0; subpass < 8; ++subpass) {
      const int cx = subpass & 1, cy = (subpass >> 1) & 1, cz = (subpass >> 2) & 1;
      if (n < 2 && subpass != 0)
        continue;
      if (stop && stop())
        return false;
      slab.exchange_halo(comm_);
      ++stats.halo_exchanges;
      const int first_k = layout.z_begin + ((layout.z_begin & 1) != cz ? 1 : 0);
      const int class_planes = first_k < layout.z_end ? (layout.z_end - first_k + 1) / 2 : 0;
      const int row = half;
      double subpass_distance = 0.0;
      std::int64_t subpass_fixed = 0;
#pragma omp parallel reduction(+ : subpass_distance, subpass_fixed)
      {
        std::optional<StencilCache> stencils;
        if (!uniform)
          stencils.emplace(h, *jacobians);
        MatchScratch scratch(exemplar);
#pragma omp for schedule(static)
        for (int plane = 0; plane < class_planes; ++plane) {
          const int k = first_k + 2 * plane;
          for (int b = 0; b < row; ++b)
            for (int a = 0; a < row; ++a) {
              const int i = 2 * a + cx, j = 2 * b + cy;
              const CorrectionStencil& stencil = stencils ? stencils->get(i, j, k) : level_stencil;
              const auto [best, distance] =
                  best_match(slab, i, j, k, stencil, exemplar, incoherent_scale, scratch);
              updates[(static_cast<std::size_t>(plane) * row + b) * row + a] = wrapped(best);
              subpass_distance += distance;
              subpass_fixed += std::llround(std::ldexp(distance, kFixedBits));
            }
        }
      }
      for (int plane = 0; plane < class_planes; ++plane)
        for (int b = 0; b < row; ++b)
          for (int a = 0; a < row; ++a)
            slab.at(2 * a + cx, 2 * b + cy, first_k + 2 * plane) =
                updates[(static_cast<std::size_t>(plane) * row + b) * row + a];
      pass_sum += subpass_distance;
      pass_fixed += subpass_fixed;
    }
    distance_sum = pass_sum;
    ++stats.passes;
    if (!counted)
      pass_fixed = 0;
    MPI_Allreduce(MPI_IN_PLACE, &pass_fixed, 1, MPI_INT64_T, MPI_SUM, comm_.raw);
    stats.pass_distances.push_back(std::ldexp(double(pass_fixed), -kFixedBits) /
                                   (double(n) * n * n));
    if (options_.min_improvement && pass > 0 &&
        double(pass_fixed) > (1.0 - *options_.min_improvement) * double(previous_fixed))
      break;
    previous_fixed = pass_fixed;
  }
  slab.exchange_halo(comm_);
  ++stats.halo_exchanges;
  const double local = counted ? distance_sum : 0.0;
  double total = 0.0;
  MPI_Allreduce(&local, &total, 1, MPI_DOUBLE, MPI_SUM, comm_.raw);
  stats.mean_match_distance = total / (double(n) * n * n);
  return true;
}

} // namespace texsim::pipelines::solid_synthesis
