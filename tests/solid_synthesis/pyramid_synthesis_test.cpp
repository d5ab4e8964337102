// Pyramid synthesis end to end in one process: the same bytes on any rank count (the run on the
// world communicator against one on MPI_COMM_SELF), near-zero neighbourhood error from an
// exactly tiling exemplar, lower error with correction passes than without, fewer incoherent
// voxels on bricks with the coherence parameter, and stripes turned by a slant field.
#include "par/gather_to_root.hpp"
#include "pipelines/solid_synthesis/anisometric_field.hpp"
#include "pipelines/solid_synthesis/appearance_space.hpp"
#include "pipelines/solid_synthesis/pyramid_synthesizer.hpp"
#include "pipelines/solid_synthesis/result_quality.hpp"
#include "pipelines/solid_synthesis/similarity_sets.hpp"
#include "pipelines/solid_synthesis/synthesis_coherence.hpp"
#include "pipelines/solid_synthesis/synthesis_exemplar.hpp"
#include "pipelines/solid_synthesis/synthesis_metrics.hpp"
#include "vol/procedural_exemplars.hpp"

#include <gtest/gtest.h>
#include <mpi.h>

#include <Eigen/Core>

#include <cmath>
#include <map>
#include <memory>
#include <optional>

namespace texsim::pipelines::solid_synthesis {
namespace {

par::Comm self_comm() {
  return {MPI_COMM_SELF, 0, 1};
}

/// An exemplar with its appearance space and the similarity sets a pyramid of `levels` needs.
struct Prepared {
  AppearanceSpace space;
  std::vector<SimilaritySets> sets;
};

Prepared prepare(const vol::RgbGrid& exemplar, int levels) {
  Prepared prepared;
  prepared.space = build_appearance_space(vol::to_channels(exemplar), AppearanceOptions{});
  prepared.sets.resize(prepared.space.levels.size());
  for (const int s : corrected_stack_levels(prepared.space, levels))
    prepared.sets[s] =
        build_similarity_sets(par::world(), prepared.space.levels[s].features, SimilarityOptions{});
  return prepared;
}

/// The finest level's exemplar positions (x fastest) and colours, gathered on rank 0 of `comm`.
struct Synthesized {
  std::vector<Position> coordinates;
  vol::ChannelGrid colours;
};

/// Options beyond the usual ones, and what the levels reported.
struct Tuning {
  std::optional<double> min_improvement;
  double finest_jitter = 0.0;
  std::vector<LevelStats> levels;
  double jitter = 0.7;
};

Synthesized synthesize(const par::Comm& comm, const Prepared& prepared, int levels, int passes,
                       const AxesField* field = nullptr, double coherence = 0.0,
                       double* incoherent = nullptr,
                       std::unique_ptr<CoordinateSlab>* slab_out = nullptr,
                       Tuning* tuning = nullptr) {
  SynthesisOptions options;
  options.levels = levels;
  options.correction_passes = passes;
  options.seed = 7;
  options.coherence = coherence;
  if (tuning) {
    options.min_improvement = tuning->min_improvement;
    options.finest_jitter = tuning->finest_jitter;
    options.jitter = tuning->jitter;
  }
  const PyramidSynthesizer synthesizer(comm, make_synthesis_exemplar(prepared.space, prepared.sets),
                                       options, field);
  LevelStats stats;
  CoordinateSlab slab = synthesizer.first_level(stats);
  for (int level = 1; level <= levels; ++level) {
    slab = *synthesizer.next_level(slab, stats); // no stop check: always a level
    if (tuning)
      tuning->levels.push_back(stats);
  }
  const int n = 1 << levels;
  if (incoherent)
    *incoherent =
        incoherent_fraction(comm, slab, nullptr, prepared.space.colours.dims(), {n, n, n});
  const auto owned = slab.layout().replicated && !comm.is_root()
                         ? std::span<const Position>()
                         : std::span<const Position>(slab.owned());
  auto coordinates = par::gather_to_root(comm, owned);
  const vol::ChannelGrid& exemplar = prepared.space.colours;
  vol::ChannelGrid colours;
  if (comm.is_root()) {
    colours = vol::ChannelGrid({n, n, n}, exemplar.channels());
    for (std::size_t v = 0; v < coordinates.size(); ++v) {
      const Coord c = coordinates[v].voxel();
      const auto colour = exemplar.voxel(exemplar.index(c.x, c.y, c.z));
      std::copy(colour.begin(), colour.end(), colours.voxel(v).begin());
    }
  }
  if (slab_out)
    *slab_out = std::make_unique<CoordinateSlab>(std::move(slab));
  return {std::move(coordinates), std::move(colours)};
}

double error_of(const Prepared& prepared, const vol::ChannelGrid& colours) {
  const auto& finest = prepared.space.levels.front();
  return neighbourhood_error(
      colours, finest.features,
      [&](const vol::ChannelGrid& grid, int i, int j, int k, std::span<float> out) {
        project_neighbourhood(finest, grid, i, j, k, out);
      },
      2);
}

TEST(PyramidSynthesis, SameBytesOnAnyRankCount) {
  const Prepared prepared = prepare(vol::marble_exemplar(16, 3), 5);
  const auto slant = rotation_field(Eigen::Vector3d::UnitZ(), 30.0);
  for (const AxesField* field :
       {static_cast<const AxesField*>(nullptr), static_cast<const AxesField*>(slant.get())}) {
    const Synthesized distributed = synthesize(par::world(), prepared, 5, 2, field);
    if (par::world().rank != 0)
      continue;
    const Synthesized serial = synthesize(self_comm(), prepared, 5, 2, field);
    ASSERT_EQ(serial.coordinates.size(), std::size_t{32 * 32 * 32});
    EXPECT_TRUE(distributed.coordinates == serial.coordinates)
        << (field ? "anisometric" : "isometric") << " synthesis differs from the serial one on "
        << par::world().size << " ranks";
  }
}

/// How many 6-neighbour erosions it takes to remove every mortar voxel (green above 0.5: light
/// mortar against red bricks) from an n^3 colour grid: half the thickness of the thickest mortar.
/// A mortar-coloured blob takes many more than the exemplar's thin joints.
int mortar_erosions(const vol::ChannelGrid& colours) {
  const int n = colours.dims().nx;
  std::vector<char> mortar(std::size_t(n) * n * n);
  for (std::size_t v = 0; v < mortar.size(); ++v)
    mortar[v] = colours.voxel(v)[1] > 0.5f;
  int erosions = 0;
  while (std::count(mortar.begin(), mortar.end(), 1) > 0) {
    std::vector<char> kept(mortar.size(), 0);
    for (int k = 0; k < n; ++k)
      for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
          const auto at = [&](int x, int y, int z) {
            return mortar[(std::size_t((z + n) % n) * n + std::size_t((y + n) % n)) * n +
                          std::size_t((x + n) % n)];
          };
          kept[(std::size_t(k) * n + j) * n + i] =
              at(i, j, k) && at(i - 1, j, k) && at(i + 1, j, k) && at(i, j - 1, k) &&
              at(i, j + 1, k) && at(i, j, k - 1) && at(i, j, k + 1);
        }
    mortar = std::move(kept);
    ++erosions;
  }
  return erosions;
}

// The shipped bricks.yaml (coherence 4, 2 passes, no jitter at the finest level) at reduced size,
// 32^3 -> 64^3, against the same with the coarser levels' jitter (0.7) at the finest level too:
// far fewer speckles, closer neighbourhoods, and still many patches rather than one copy, with no
// mortar blob thicker than the exemplar's joints. The 32^3 exemplar's joints are under a voxel
// wide, so the figures are worse than the shipped 64^3 run's (0.7% incoherent, error 0.044):
// measured here 4.0% and 0.137 (finest jitter 0.7: 13.7% and 0.159); the bounds leave a margin.
TEST(PyramidSynthesis, ShippedBricksAtReducedSizeAreCleanAndVaried) {
  const Prepared prepared = prepare(vol::brick_exemplar(32, 1), 6);
  const vol::Dims dims = prepared.space.colours.dims();
  struct Figures {
    double incoherent = 0, error = 0, share = 0;
    int erosions = 0;
  };
  const auto run = [&](double finest_jitter) {
    Figures f;
    std::unique_ptr<CoordinateSlab> slab;
    Tuning tuning{std::nullopt, finest_jitter, {}};
    const Synthesized result =
        synthesize(par::world(), prepared, 6, 2, nullptr, 4.0, &f.incoherent, &slab, &tuning);
    f.share = largest_offset_share(par::world(), *slab, nullptr, dims, {64, 64, 64});
    if (par::world().rank == 0) {
      f.error = error_of(prepared, result.colours);
      f.erosions = mortar_erosions(result.colours);
    }
    return f;
  };
  const Figures shipped = run(0.0), jittered = run(0.7);
  if (par::world().rank != 0)
    return;
  const int exemplar_erosions = mortar_erosions(prepared.space.colours);
  for (const auto& [name, f] : {std::pair{"finest jitter 0", shipped}, {"0.7", jittered}})
    std::printf("bricks 32 -> 64, %s: incoherent %.4f, neighbourhood error %.4f, largest offset "
                "share %.3f, mortar erosions %d (exemplar %d)\n",
                name, f.incoherent, f.error, f.share, f.erosions, exemplar_erosions);
  EXPECT_LE(shipped.incoherent, 0.05);
  EXPECT_LT(shipped.incoherent, 0.5 * jittered.incoherent);
  EXPECT_LE(shipped.error, 0.15);
  EXPECT_LT(shipped.error, jittered.error);
  EXPECT_LE(shipped.share, 0.25);
  EXPECT_LE(shipped.erosions, exemplar_erosions);
}

/// The finest level's A under `field` on this rank's planes of `slab` and its halo.
LevelJacobians finest_jacobians(const AxesField& field, const CoordinateSlab& slab) {
  return sample_level(field, slab.size(), slab.layout().z_begin - kSlabHalo,
                      slab.layout().z_end + kSlabHalo, slab.size());
}

TEST(PyramidSynthesis, FieldFrameErrorIsZeroForAnExactlyTurnedCopy) {
  // S(p) = A p + c kept to 1/256 voxel: the bricks turned by 30 degrees about z, nothing else.
  // Read in the field's frame every window is one of the exemplar's; read axis-aligned, every
  // turned joint counts as an error.
  const Prepared prepared = prepare(vol::brick_exemplar(32, 1), 5);
  const auto slant = rotation_field(Eigen::Vector3d::UnitZ(), 30.0);
  CoordinateSlab slab(level_layout(5, par::world().rank, par::world().size));
  const LevelJacobians jacobians = finest_jacobians(*slant, slab);
  const Eigen::Matrix3f a = jacobians.a(0, 0, slab.layout().z_begin);
  // Continuous on [-4, 28) per axis (a turned copy cannot wrap with the 32-voxel level): the
  // windows of the samples in [0, 24) stay inside.
  const auto unwrapped = [](int v) { return float(v >= 28 ? v - 32 : v); };
  for (int k = slab.layout().z_begin; k < slab.layout().z_end; ++k)
    for (int j = 0; j < 32; ++j)
      for (int i = 0; i < 32; ++i) {
        const Eigen::Vector3f s =
            256.0f * (a * Eigen::Vector3f(unwrapped(i), unwrapped(j), unwrapped(k)) +
                      Eigen::Vector3f(5.3f, 2.1f, 9.7f));
        slab.at(i, j, k) = {int(std::lround(s.x())), int(std::lround(s.y())),
                            int(std::lround(s.z()))};
      }
  slab.exchange_halo(par::world());
  const auto& finest = prepared.space.levels.front();
  const auto& colours = prepared.space.colours;
  const double framed =
      slab_neighbourhood_error(par::world(), slab, &jacobians, {24, 24, 24}, finest, colours, 2);
  const double axis_aligned =
      slab_neighbourhood_error(par::world(), slab, nullptr, {24, 24, 24}, finest, colours, 2);
  std::printf("exactly turned bricks: neighbourhood error %.4f in the field's frame, %.4f "
              "axis-aligned\n",
              framed, axis_aligned);
  EXPECT_LE(framed, 0.01);
  EXPECT_GT(axis_aligned, 0.1);
  EXPECT_EQ(largest_offset_share(par::world(), slab, &a, colours.dims(), {24, 24, 24}), 1.0);
}

// The shipped anisometric settings (coherence 8, jitter 0.05) at reduced size, 32^3 -> 64^3:
// bricks under a 30 degree slant and wood under the circular field, against the shipped isometric
// bricks at the same size. The targets: neighbourhood error (in the field's frame) at most
// 1.5 times the isometric run's and at most 3% incoherent voxels; and the slant run is not one
// big turned copy (largest offset share at most 0.25, the isometric bricks test's bound). Measured:
// isometric error 0.137, 4.0% incoherent, largest offset share 0.08; slant 0.063, 0.1%, 0.18;
// circular wood 0.161, 2.0% (with A_p alone in the predictions instead of the two ends' mean:
// 0.162, 2.4%).
TEST(PyramidSynthesis, ShippedAnisometricSettingsAtReducedSizeAreAsGoodAsIsometric) {
  const Prepared bricks = prepare(vol::brick_exemplar(32, 1), 6);
  const Prepared wood = prepare(vol::wood_exemplar(32, 1), 6);
  const auto slant = rotation_field(Eigen::Vector3d::UnitZ(), 30.0);
  const auto circular = ellipse_field(1.0);
  struct Figures {
    double incoherent = 0, error = 0, share = -1;
  };
  const auto run = [&](const Prepared& prepared, const AxesField* field, double coherence,
                       double jitter) {
    Figures f;
    std::unique_ptr<CoordinateSlab> slab;
    Tuning tuning{std::nullopt, 0.0, {}, jitter};
    synthesize(par::world(), prepared, 6, 2, field, coherence, nullptr, &slab, &tuning);
    slab->exchange_halo(par::world());
    std::optional<LevelJacobians> jacobians;
    if (field)
      jacobians = finest_jacobians(*field, *slab);
    const LevelJacobians* a = jacobians ? &*jacobians : nullptr;
    const vol::Dims dims = prepared.space.colours.dims();
    f.incoherent = incoherent_fraction(par::world(), *slab, a, dims, {64, 64, 64});
    f.error = slab_neighbourhood_error(par::world(), *slab, a, {64, 64, 64},
                                       prepared.space.levels.front(), prepared.space.colours, 2);
    const std::optional<Eigen::Matrix3f> uniform =
        a ? uniform_jacobian(par::world(), *a)
          : std::optional(Eigen::Matrix3f(Eigen::Matrix3f::Identity()));
    if (uniform)
      f.share = largest_offset_share(par::world(), *slab, &*uniform, dims, {64, 64, 64});
    return f;
  };
  const Figures isometric = run(bricks, nullptr, 4.0, 0.7);
  const Figures turned = run(bricks, slant.get(), 8.0, 0.05);
  const Figures bent = run(wood, circular.get(), 8.0, 0.05);
  if (par::world().rank != 0)
    return;
  for (const auto& [name, f] : {std::pair{"isometric bricks", isometric},
                                {"slant bricks", turned},
                                {"circular wood", bent}})
    std::printf("32 -> 64, %s: error %.4f, incoherent %.4f, largest offset share %.3f\n", name,
                f.error, f.incoherent, f.share);
  EXPECT_LE(turned.error, 1.5 * isometric.error);
  EXPECT_LE(turned.incoherent, 0.03);
  EXPECT_LE(turned.share, 0.25);
  EXPECT_LE(bent.error, 1.5 * isometric.error);
  EXPECT_LE(bent.incoherent, 0.03);
  EXPECT_EQ(bent.share, -1.0); // a varying field has no constant offset
}

TEST(PyramidSynthesis, AdaptivePassesStopWhenTheErrorStopsFalling) {
  // Each pass but the last lowered the level's match distance by at least min_improvement; the
  // last did not, or was the most allowed. The decision rests on exact sums: the same passes and
  // the same bytes on any rank count.
  const Prepared prepared = prepare(vol::brick_exemplar(16, 3), 5);
  Tuning distributed{0.05, 0.0, {}};
  const Synthesized result =
      synthesize(par::world(), prepared, 5, 8, nullptr, 0.0, nullptr, nullptr, &distributed);
  int stopped_early = 0;
  for (const LevelStats& level : distributed.levels) {
    if (!level.corrected)
      continue;
    const auto& d = level.pass_distances;
    ASSERT_EQ(int(d.size()), level.passes);
    ASSERT_GE(level.passes, 1);
    for (int p = 1; p + 1 < level.passes; ++p)
      EXPECT_LE(d[p], 0.95 * d[p - 1] * (1 + 1e-12)) << "level " << level.level << " pass " << p;
    if (level.passes < 8) {
      ++stopped_early;
      EXPECT_GT(d.back(), 0.95 * d[d.size() - 2] * (1 - 1e-12)) << "level " << level.level;
    }
  }
  EXPECT_GT(stopped_early, 0);
  if (par::world().rank != 0)
    return;
  Tuning serial{0.05, 0.0, {}};
  const Synthesized reference =
      synthesize(self_comm(), prepared, 5, 8, nullptr, 0.0, nullptr, nullptr, &serial);
  ASSERT_EQ(serial.levels.size(), distributed.levels.size());
  for (std::size_t l = 0; l < serial.levels.size(); ++l)
    EXPECT_EQ(serial.levels[l].pass_distances, distributed.levels[l].pass_distances);
  EXPECT_TRUE(result.coordinates == reference.coordinates);
}

TEST(PyramidSynthesis, LargestOffsetShareCountsTheBiggestCopy) {
  // Against a count over the gathered volume; then a shifted copy of the exemplar (one offset)
  // and two half-volume copies (two offsets of half the voxels each).
  const Prepared prepared = prepare(vol::marble_exemplar(16, 3), 5);
  std::unique_ptr<CoordinateSlab> slab;
  const Synthesized result = synthesize(par::world(), prepared, 5, 2, nullptr, 0.0, nullptr, &slab);
  const vol::Dims exemplar = prepared.space.colours.dims();
  const double synthesized =
      largest_offset_share(par::world(), *slab, nullptr, exemplar, {32, 32, 32});
  if (par::world().rank == 0) {
    std::map<std::array<int, 3>, int> voxels_per_offset;
    for (std::size_t v = 0; v < result.coordinates.size(); ++v) {
      const int i = int(v % 32), j = int(v / 32 % 32), k = int(v / 1024);
      const Coord c = result.coordinates[v].voxel();
      ++voxels_per_offset[{(c.x - i + 64) % 16, (c.y - j + 64) % 16, (c.z - k + 64) % 16}];
    }
    int most = 0;
    for (const auto& [offset, count] : voxels_per_offset)
      most = std::max(most, count);
    EXPECT_EQ(synthesized, double(most) / (32 * 32 * 32));
    EXPECT_GT(voxels_per_offset.size(), 10u);
  }
  const LevelLayout& layout = slab->layout();
  const auto copies_split_at =
      [&](int split) { // offset (3, 5, 7) below plane `split`, (4, 5, 7) above
        for (int k = layout.z_begin; k < layout.z_end; ++k)
          for (int j = 0; j < 32; ++j)
            for (int i = 0; i < 32; ++i)
              slab->at(i, j, k) =
                  Position::at_voxel({(i + (k < split ? 3 : 4)) % 16, (j + 5) % 16, (k + 7) % 16});
        return largest_offset_share(par::world(), *slab, nullptr, exemplar, {32, 32, 32});
      };
  EXPECT_EQ(copies_split_at(32), 1.0);
  EXPECT_EQ(copies_split_at(16), 0.5);
}

TEST(PyramidSynthesis, SlabMetricsEqualTheWholeVolumesOnAnyRankCount) {
  // Each rank measures its own slab; the figures are those of the whole volume, to the bit.
  const Prepared prepared = prepare(vol::marble_exemplar(16, 3), 5);
  std::unique_ptr<CoordinateSlab> slab;
  const Synthesized result = synthesize(par::world(), prepared, 5, 1, nullptr, 0.0, nullptr, &slab);
  slab->exchange_halo(par::world());
  const auto& finest = prepared.space.levels.front();
  const auto& exemplar = prepared.space.colours;
  const double slab_error =
      slab_neighbourhood_error(par::world(), *slab, nullptr, {32, 32, 32}, finest, exemplar, 2);
  const double slab_histogram =
      slab_histogram_distance(par::world(), *slab, {32, 32, 32}, exemplar);
  if (par::world().rank != 0)
    return;
  EXPECT_EQ(slab_error, error_of(prepared, result.colours));
  EXPECT_EQ(slab_histogram, histogram_distance(result.colours, exemplar));
  EXPECT_GT(slab_error, 0.0);
  EXPECT_GT(slab_histogram, 0.0);
}

TEST(PyramidSynthesis, TilingExemplarGivesNearZeroNeighbourhoodError) {
  // Period 8 inside a 32^3 exemplar: every coordinate has 64 equivalent copies, and a coherent
  // result reproduces the lattice exactly.
  const Prepared prepared = prepare(vol::lattice_exemplar(32, 8, 5), 5);
  const Synthesized corrected = synthesize(par::world(), prepared, 5, 4);
  const Synthesized jittered = synthesize(par::world(), prepared, 5, 0);
  if (par::world().rank != 0)
    return;
  const double error = error_of(prepared, corrected.colours);
  const double random_error = error_of(prepared, jittered.colours);
  std::printf("tiling exemplar: neighbourhood error %.4f corrected, %.4f uncorrected\n", error,
              random_error);
  EXPECT_LT(error, 0.05);
  EXPECT_LT(error, 0.1 * random_error);
}

TEST(PyramidSynthesis, CorrectionPassesLowerTheNeighbourhoodError) {
  const Prepared prepared = prepare(vol::marble_exemplar(32, 11), 5);
  std::vector<double> errors;
  for (const int passes : {0, 1, 3}) {
    const Synthesized result = synthesize(par::world(), prepared, 5, passes);
    if (par::world().rank == 0)
      errors.push_back(error_of(prepared, result.colours));
  }
  if (par::world().rank != 0)
    return;
  std::printf("marble: neighbourhood error %.4f / %.4f / %.4f after 0 / 1 / 3 passes\n", errors[0],
              errors[1], errors[2]);
  EXPECT_LT(errors[1], 0.8 * errors[0]);
  EXPECT_LE(errors[2], errors[1] * 1.02);
}

TEST(PyramidSynthesis, TheCoherenceParameterKeepsBrickPatchesWhole) {
  const Prepared prepared = prepare(vol::brick_exemplar(32, 1), 6);
  double plain = 0.0, biased = 0.0;
  const Synthesized a = synthesize(par::world(), prepared, 6, 2, nullptr, 0.0, &plain);
  const Synthesized b = synthesize(par::world(), prepared, 6, 2, nullptr, 4.0, &biased);
  if (par::world().rank != 0)
    return;
  const double error_plain = error_of(prepared, a.colours),
               error_biased = error_of(prepared, b.colours);
  std::printf("bricks: incoherent voxels %.4f -> %.4f, neighbourhood error %.4f -> %.4f with "
              "coherence 4\n",
              plain, biased, error_plain, error_biased);
  EXPECT_LT(biased, 0.5 * plain);
  EXPECT_LT(error_biased, error_plain);
}

TEST(PyramidSynthesis, SlantFieldTurnsStripesByItsAngle) {
  const Prepared prepared = prepare(vol::stripe_exemplar(32), 6);
  const auto slant = rotation_field(Eigen::Vector3d::UnitZ(), 30.0);
  const Synthesized isometric = synthesize(par::world(), prepared, 6, 2);
  const Synthesized turned = synthesize(par::world(), prepared, 6, 2, slant.get());
  if (par::world().rank != 0)
    return;
  const double straight = xy_stripe_orientation_degrees(isometric.colours);
  const double angle = xy_stripe_orientation_degrees(turned.colours);
  std::printf("stripes: %.1f degrees isometric, %.1f degrees under the 30 degree slant\n", straight,
              angle);
  EXPECT_NEAR(straight, 0.0, 10.0);
  EXPECT_NEAR(angle, 30.0, 10.0);
}

} // namespace
} // namespace texsim::pipelines::solid_synthesis
