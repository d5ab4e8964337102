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
#include <memory>

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

/// The finest level's exemplar coordinates (x fastest) and colours, gathered on rank 0 of `comm`.
struct Synthesized {
  std::vector<Coord> coordinates;
  vol::ChannelGrid colours;
};

Synthesized synthesize(const par::Comm& comm, const Prepared& prepared, int levels, int passes,
                       const AxesField* field = nullptr, double coherence = 0.0,
                       double* incoherent = nullptr,
                       std::unique_ptr<CoordinateSlab>* slab_out = nullptr) {
  SynthesisOptions options;
  options.levels = levels;
  options.correction_passes = passes;
  options.seed = 7;
  options.coherence = coherence;
  const PyramidSynthesizer synthesizer(comm, make_synthesis_exemplar(prepared.space, prepared.sets),
                                       options, field);
  LevelStats stats;
  CoordinateSlab slab = synthesizer.first_level(stats);
  for (int level = 1; level <= levels; ++level)
    slab = *synthesizer.next_level(slab, stats); // no stop check: always a level
  const int n = 1 << levels;
  if (incoherent)
    *incoherent =
        incoherent_fraction(comm, slab, nullptr, prepared.space.colours.dims(), {n, n, n});
  const auto owned = slab.layout().replicated && !comm.is_root()
                         ? std::span<const Coord>()
                         : std::span<const Coord>(slab.owned());
  auto coordinates = par::gather_to_root(comm, owned);
  const vol::ChannelGrid& exemplar = prepared.space.colours;
  vol::ChannelGrid colours;
  if (comm.is_root()) {
    colours = vol::ChannelGrid({n, n, n}, exemplar.channels());
    for (std::size_t v = 0; v < coordinates.size(); ++v) {
      const Coord& c = coordinates[v];
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

TEST(PyramidSynthesis, SlabMetricsEqualTheWholeVolumesOnAnyRankCount) {
  // Each rank measures its own slab; the figures are those of the whole volume, to the bit.
  const Prepared prepared = prepare(vol::marble_exemplar(16, 3), 5);
  std::unique_ptr<CoordinateSlab> slab;
  const Synthesized result = synthesize(par::world(), prepared, 5, 1, nullptr, 0.0, nullptr, &slab);
  slab->exchange_halo(par::world());
  const auto& finest = prepared.space.levels.front();
  const auto& exemplar = prepared.space.colours;
  const double slab_error =
      slab_neighbourhood_error(par::world(), *slab, {32, 32, 32}, finest, exemplar, 2);
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
