// Similarity sets against a brute-force reference written here from the definition (double
// distances, an explicit window-exclusion loop over every voxel), on random, smooth and
// quantised (tie-heavy) features, periodic and not, several k and window sizes, grids whose rows
// do not fill whole SIMD chunks, and at every rank count the test runs with, for both searches
// (kd-tree and scan). Plus the cache file.
#include "core/rng.hpp"
#include "par/comm.hpp"
#include "pipelines/solid_synthesis/feature_twins.hpp"
#include "pipelines/solid_synthesis/similarity_set_cache.hpp"
#include "pipelines/solid_synthesis/similarity_sets.hpp"
#include "support/test_data.hpp"
#include "support/test_files.hpp"

#include <gtest/gtest.h>
#include <mpi.h>

#include <array>
#include <cmath>
#include <cstdlib>
#include <filesystem>

namespace texsim::pipelines::solid_synthesis {
namespace {

enum class Pattern { random, smooth, quantised, twins };

/// Features of `channels` floats per voxel: iid uniform; a sum of low-frequency waves (nearest
/// neighbours in feature space are spatial neighbours, so the windows decide the answer); or
/// uniform values rounded to three levels on two channels (large classes of exactly equal
/// features, so ties decide the answer); or iid uniform with small groups of copies (every 5th
/// voxel copies its x neighbour, inside its window; every 13th a voxel far away), so that some
/// queries' twins decide their sets and others have too few twins outside the windows.
vol::ChannelGrid make_features(vol::Dims dims, int channels, Pattern pattern, std::uint64_t seed) {
  const CounterRng rng(seed, 11);
  vol::ChannelGrid grid(dims, pattern == Pattern::quantised ? 2 : channels);
  for (int z = 0; z < dims.nz; ++z)
    for (int y = 0; y < dims.ny; ++y)
      for (int x = 0; x < dims.nx; ++x) {
        const std::size_t v = grid.index(x, y, z);
        auto f = grid.voxel(v);
        for (int c = 0; c < grid.channels(); ++c) {
          const double u = rng.uniform(v, 0, static_cast<std::uint32_t>(c));
          if (pattern == Pattern::random) {
            f[c] = static_cast<float>(u);
          } else if (pattern == Pattern::quantised) {
            f[c] = static_cast<float>(std::floor(3.0 * u) / 3.0);
          } else {
            double sum = 0.0;
            for (int wave = 0; wave < 3; ++wave) {
              const double kx = 1 + (c + wave) % 2, ky = 1 + (c + 2 * wave) % 3, kz = 1 + wave % 2;
              const double phase = rng.uniform(1000 + c, 0, static_cast<std::uint32_t>(wave));
              sum += std::sin(2.0 * M_PI *
                              (kx * x / dims.nx + ky * y / dims.ny + kz * z / dims.nz + phase));
            }
            f[c] = static_cast<float>(sum + 0.01 * u);
          }
        }
      }
  if (pattern == Pattern::twins) {
    const auto n = static_cast<std::int64_t>(grid.voxel_count());
    for (std::int64_t v = 1; v < n; ++v) {
      const std::int64_t source = v % 5 == 0 ? v - 1 : v % 13 == 0 ? v * 7919 % n : v;
      if (source != v)
        std::copy_n(grid.voxel(std::size_t(source)).begin(), grid.channels(),
                    grid.voxel(std::size_t(v)).begin());
    }
  }
  return grid;
}

std::array<int, 3> coordinates(vol::Dims dims, std::int32_t v) {
  return {v % dims.nx, v / dims.nx % dims.ny, v / (dims.nx * dims.ny)};
}

/// Whether voxel b lies in the n x n x n window centred on voxel a.
bool in_window(vol::Dims dims, const SimilarityOptions& options, const std::array<int, 3>& a,
               const std::array<int, 3>& b) {
  const int sizes[3] = {dims.nx, dims.ny, dims.nz};
  for (int axis = 0; axis < 3; ++axis) {
    int d = std::abs(a[axis] - b[axis]);
    if (options.periodic)
      d = std::min(d, sizes[axis] - d);
    if (d > options.window / 2)
      return false;
  }
  return true;
}

/// The similarity sets straight from the definition, one voxel at a time: all distances, then
/// k - 1 rounds of "the best voxel not yet excluded; exclude its window".
class Reference {
public:
  Reference(const vol::ChannelGrid& features, const SimilarityOptions& options)
      : features_(features), options_(options) {
    for (std::int32_t v = 0; v < static_cast<std::int32_t>(features.voxel_count()); ++v)
      at_.push_back(coordinates(features.dims(), v));
  }

  std::vector<std::int32_t> set(std::int32_t p) const {
    const auto n = static_cast<std::int32_t>(features_.voxel_count());
    std::vector<double> distance(static_cast<std::size_t>(n));
    const auto fp = features_.voxel(static_cast<std::size_t>(p));
    for (std::int32_t q = 0; q < n; ++q) {
      const auto fq = features_.voxel(static_cast<std::size_t>(q));
      double sum = 0.0;
      for (std::size_t c = 0; c < fp.size(); ++c) {
        const double diff = static_cast<double>(fq[c]) - static_cast<double>(fp[c]);
        sum += diff * diff;
      }
      distance[static_cast<std::size_t>(q)] = sum;
    }
    std::vector<bool> excluded(static_cast<std::size_t>(n));
    const auto exclude_window_of = [&](std::int32_t centre) {
      for (std::int32_t q = 0; q < n; ++q)
        if (in_window(features_.dims(), options_, at_[centre], at_[q]))
          excluded[q] = true;
    };
    std::vector<std::int32_t> set{p};
    exclude_window_of(p);
    while (static_cast<int>(set.size()) < options_.k) {
      std::int32_t best = -1;
      // Ascending q and a strict comparison: ties go to the smaller index.
      for (std::int32_t q = 0; q < n; ++q)
        if (!excluded[q] && (best < 0 || distance[q] < distance[best]))
          best = q;
      if (best < 0) {
        set.push_back(set.back());
        continue;
      }
      set.push_back(best);
      exclude_window_of(best);
    }
    return set;
  }

private:
  const vol::ChannelGrid& features_;
  SimilarityOptions options_;
  std::vector<std::array<int, 3>> at_;
};

/// Voxels (every `stride`-th, split over the ranks) whose sets in `searched` (the tree's, then the
/// scan's) differ from the reference, summed over ranks and searches. The reference, the costly
/// part, is computed once for both. Collective.
long mismatches(const par::Comm& comm, const vol::ChannelGrid& features,
                const SimilarityOptions& options, const std::vector<SimilaritySets>& searched,
                int stride) {
  long wrong = 0;
  const Reference reference(features, options);
  const auto n = static_cast<std::int32_t>(features.voxel_count());
  for (std::int32_t v = comm.rank * stride; v < n; v += comm.size * stride) {
    const auto expected = reference.set(v);
    for (std::size_t s = 0; s < searched.size(); ++s) {
      const SimilaritySets& sets = searched[s];
      const std::vector<std::int32_t> got(sets.candidates.begin() + v * sets.k,
                                          sets.candidates.begin() + (v + 1) * sets.k);
      if (got != expected) {
        if (wrong < 3)
          ADD_FAILURE() << (s == 0 ? "tree" : "scan") << ", voxel " << v << ": C_2.. = " << got[1]
                        << " ... expected " << expected[1] << " ...";
        ++wrong;
      }
    }
  }
  long total = 0;
  MPI_Allreduce(&wrong, &total, 1, MPI_LONG, MPI_SUM, comm.raw);
  return total;
}

struct Case {
  const char* name;
  vol::Dims dims;
  int channels;
  Pattern pattern;
  SimilarityOptions options;
  int stride; ///< reference check on every stride-th voxel
};

const Case kCases[] = {
    {"random_16_periodic_k3_n7", {16, 16, 16}, 8, Pattern::random, {3, 7, true}, 1},
    {"random_16_open_k5_n3", {16, 16, 16}, 8, Pattern::random, {5, 3, false}, 1},
    {"smooth_16_periodic_k5_n7", {16, 16, 16}, 4, Pattern::smooth, {5, 7, true}, 1},
    {"smooth_16_open_k3_n3", {16, 16, 16}, 8, Pattern::smooth, {3, 3, false}, 1},
    {"random_24_periodic_k3_n7", {24, 24, 24}, 8, Pattern::random, {3, 7, true}, 7},
    {"smooth_24_open_k3_n7", {24, 24, 24}, 8, Pattern::smooth, {3, 7, false}, 7},
    {"smooth_24_periodic_k5_n3", {24, 24, 24}, 8, Pattern::smooth, {5, 3, true}, 7},
    {"random_24_open_k5_n7", {24, 24, 24}, 3, Pattern::random, {5, 7, false}, 7},
    {"ties_16_periodic_k3_n7", {16, 16, 16}, 2, Pattern::quantised, {3, 7, true}, 1},
    {"ties_24_open_k5_n3", {24, 24, 24}, 2, Pattern::quantised, {5, 3, false}, 7},
    {"twins_16_periodic_k3_n7", {16, 16, 16}, 4, Pattern::twins, {3, 7, true}, 1},
    {"twins_17x16x15_open_k5_n3", {17, 16, 15}, 8, Pattern::twins, {5, 3, false}, 1},
    // Rows of 19 and 33 voxels: partial SIMD chunks; flat grids: windows wrap onto themselves.
    {"smooth_19x13x11_periodic_k5_n7", {19, 13, 11}, 8, Pattern::smooth, {5, 7, true}, 1},
    {"random_33x9x4_open_k3_n7", {33, 9, 4}, 8, Pattern::random, {3, 7, false}, 1},
    // Windows cover (nearly) everything: the last candidate repeats.
    {"random_6x5x4_periodic_k3_n7", {6, 5, 4}, 8, Pattern::random, {3, 7, true}, 1},
    {"random_8_open_k5_n7", {8, 8, 8}, 8, Pattern::random, {5, 7, false}, 1},
    {"random_8_periodic_k1", {8, 8, 8}, 8, Pattern::random, {1, 7, true}, 1},
};

TEST(SimilaritySets, EqualBruteForceReference) {
  const par::Comm comm = par::world();
  for (const Case& c : kCases) {
    SCOPED_TRACE(c.name);
    const auto features = make_features(c.dims, c.channels, c.pattern, 7);
    std::vector<SimilaritySets> searched;
    for (const auto search : {ShortlistSearch::tree, ShortlistSearch::scan}) {
      SimilarityOptions options = c.options;
      options.search = search;
      searched.push_back(build_similarity_sets(comm, features, options));
      EXPECT_EQ(searched.back().dims, c.dims);
      ASSERT_EQ(searched.back().k, c.options.k);
      ASSERT_EQ(searched.back().candidates.size(), c.dims.count() * c.options.k);
    }
    EXPECT_EQ(mismatches(comm, features, c.options, searched, c.stride), 0);
  }
}

TEST(SimilaritySets, TreeAndScanGiveTheSameSetsOnLargerGrids) {
  // Beyond the reference's reach: the two searches agree on every voxel of 32^3 grids.
  const par::Comm comm = par::world();
  for (const auto pattern :
       {Pattern::smooth, Pattern::random, Pattern::quantised, Pattern::twins}) {
    const auto features = make_features({32, 32, 32}, 8, pattern, 5);
    for (const bool periodic : {true, false}) {
      SimilarityOptions options{3, 7, periodic};
      options.search = ShortlistSearch::tree;
      const auto tree = build_similarity_sets(comm, features, options);
      options.search = ShortlistSearch::scan;
      const auto scan = build_similarity_sets(comm, features, options);
      EXPECT_EQ(tree.candidates, scan.candidates)
          << "pattern " << static_cast<int>(pattern) << (periodic ? " periodic" : " open");
    }
  }
}

TEST(SimilaritySets, AutomaticSearchScansOnlySmallGrids) {
  EXPECT_EQ(automatic_search(make_features({32, 32, 32}, 8, Pattern::smooth, 1)),
            ShortlistSearch::tree);
  EXPECT_EQ(automatic_search(make_features({16, 16, 16}, 8, Pattern::smooth, 1)),
            ShortlistSearch::scan);
  EXPECT_EQ(automatic_search(make_features({32, 32, 32}, 2, Pattern::quantised, 1)),
            ShortlistSearch::tree);
}

TEST(SimilaritySets, TwinsAreTheVoxelsWithEqualFeaturesInIndexOrder) {
  vol::ChannelGrid features({5, 1, 1}, 2);
  const float values[5][2] = {
      {0.0f, 1.0f}, {1.0f, 0.0f}, {-0.0f, 1.0f}, {1.0f, 0.0f}, {0.0f, 1.5f}};
  for (std::size_t v = 0; v < 5; ++v)
    std::copy_n(values[v], 2, features.voxel(v).begin());
  // Sorted on rank 0 and held once per node: every rank reads the same groups.
  const FeatureTwins twins(features, par::NodeLayout::make(par::world()));
  const auto as_vector = [](std::span<const std::int32_t> s) {
    return std::vector<std::int32_t>(s.begin(), s.end());
  };
  EXPECT_EQ(as_vector(twins.of(2)), (std::vector<std::int32_t>{0, 2})); // -0 equals +0
  EXPECT_EQ(as_vector(twins.of(3)), (std::vector<std::int32_t>{1, 3}));
  EXPECT_EQ(as_vector(twins.of(4)), (std::vector<std::int32_t>{4}));
  EXPECT_EQ(twins.tied_voxels(), 4);
}

TEST(SimilaritySets, CandidatesRespectTheWindows) {
  const par::Comm comm = par::world();
  const SimilarityOptions options{5, 7, true};
  const auto features = make_features({24, 24, 24}, 8, Pattern::smooth, 3);
  const SimilaritySets sets = build_similarity_sets(comm, features, options);
  long violations = 0;
  long beside_window = 0;
  for (std::int32_t v = 0; v < static_cast<std::int32_t>(features.voxel_count()); ++v) {
    const std::int32_t* c = sets.candidates.data() + static_cast<std::size_t>(v) * options.k;
    violations += c[0] != v;
    for (int j = 1; j < options.k; ++j)
      for (int i = 0; i < j; ++i)
        violations += in_window(sets.dims, options, coordinates(sets.dims, c[i]),
                                coordinates(sets.dims, c[j]));
    // Smooth features: the best match outside p's window is mostly right beside it.
    const auto a = coordinates(sets.dims, v), b = coordinates(sets.dims, c[1]);
    int distance = 0;
    for (int axis = 0; axis < 3; ++axis) {
      const int d = std::abs(a[axis] - b[axis]);
      distance = std::max(distance, std::min(d, 24 - d));
    }
    beside_window += distance == options.window / 2 + 1;
  }
  EXPECT_EQ(violations, 0);
  // Shows the windows matter here: without them C_2 would be a direct neighbour.
  EXPECT_GT(beside_window, static_cast<long>(features.voxel_count() / 2));
}

TEST(SimilaritySets, RejectsNonFiniteFeatures) {
  const par::Comm comm = par::world();
  auto features = make_features({8, 8, 8}, 4, Pattern::random, 1);
  features.voxel(100)[2] = std::nanf("");
  EXPECT_THROW(build_similarity_sets(comm, features, {}), Error);
}

TEST(SimilaritySetCache, KeyNamesFeaturesAndOptions) {
  auto features = make_features({8, 8, 8}, 4, Pattern::random, 1);
  const SimilarityOptions options;
  const std::string key = similarity_cache_key(features, options);
  EXPECT_EQ(key.rfind("8x8x8x4-k3-n7-torus-", 0), 0u) << key;
  EXPECT_EQ(similarity_cache_key(make_features({8, 8, 8}, 4, Pattern::random, 1), options), key);
  EXPECT_NE(similarity_cache_key(features, {5, 7, true}), key);
  EXPECT_NE(similarity_cache_key(features, {3, 5, true}), key);
  EXPECT_NE(similarity_cache_key(features, {3, 7, false}), key);
  features.voxel(511)[3] += 1e-6f;
  EXPECT_NE(similarity_cache_key(features, options), key);
}

TEST(SimilaritySetCache, RoundTripAndRefusals) {
  const par::Comm comm = par::world();
  const auto dir = test::scratch_dir("similarity_set_cache");
  const auto file = dir / "cache" / "sets.h5"; // the directory does not exist yet
  const SimilarityOptions options{4, 5, false};
  const auto features = make_features({12, 10, 9}, 6, Pattern::smooth, 2);
  const std::string key = similarity_cache_key(features, options);
  const SimilaritySets sets = build_similarity_sets(comm, features, options);

  EXPECT_FALSE(load_similarity_sets(comm, file, key).has_value()) << "no file yet";
  save_similarity_sets(comm, file, key, sets);
  const auto loaded = load_similarity_sets(comm, file, key);
  ASSERT_TRUE(loaded.has_value());
  EXPECT_EQ(loaded->dims, sets.dims);
  EXPECT_EQ(loaded->k, sets.k);
  EXPECT_EQ(loaded->candidates, sets.candidates);
  EXPECT_TRUE(test::temporary_files_under(dir).empty());
  // Rank 0 writes again below: no rank may still be looking for temporary files then (a bcast
  // lets rank 0 run ahead, and a rank that saw its next temporary file failed alone).
  comm.barrier();

  const std::string other_key = similarity_cache_key(features, {4, 7, false});
  EXPECT_FALSE(load_similarity_sets(comm, file, other_key).has_value()) << "key mismatch";

  // A file holding sets that cannot be right (C_1(v) != v) is not used, whether the wrong set is
  // in the first planes (read by rank 0) or the last (read by the last rank).
  const std::size_t voxels = sets.dims.count();
  for (const std::size_t v : {std::size_t{5}, voxels - 1}) {
    std::vector<std::int32_t> wrong(sets.candidates.begin(), sets.candidates.end());
    wrong[static_cast<std::size_t>(sets.k) * v] = static_cast<std::int32_t>((v + 1) % voxels);
    const SimilaritySets broken{
        sets.dims, sets.k,
        par::NodeSharedArray<std::int32_t>::from_root(par::NodeLayout::make(comm), wrong)};
    save_similarity_sets(comm, file, key, broken);
    EXPECT_FALSE(load_similarity_sets(comm, file, key).has_value()) << "inconsistent set " << v;
    comm.barrier(); // rank 0 writes again next
  }

  // Truncated and foreign files are not used; saving again replaces them.
  save_similarity_sets(comm, file, key, sets);
  if (comm.is_root())
    std::filesystem::resize_file(file, std::filesystem::file_size(file) / 2);
  comm.barrier();
  EXPECT_FALSE(load_similarity_sets(comm, file, key).has_value()) << "truncated file";
  if (comm.is_root())
    test::write_bytes(file, test::Bytes(4096, 0x5a));
  comm.barrier();
  EXPECT_FALSE(load_similarity_sets(comm, file, key).has_value()) << "not an HDF5 file";
  save_similarity_sets(comm, file, key, sets);
  const auto again = load_similarity_sets(comm, file, key);
  ASSERT_TRUE(again.has_value());
  EXPECT_EQ(again->candidates, sets.candidates);
}

} // namespace
} // namespace texsim::pipelines::solid_synthesis
