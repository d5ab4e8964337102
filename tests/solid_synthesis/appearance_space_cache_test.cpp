// The appearance-space cache: keys name the exemplar and every option; a saved space loads back
// bit for bit on every rank (toroidal and discarded borders); a missing file, another key, a
// truncated, foreign or bit-flipped file, and a file that cannot be written all leave the caller
// to build the space itself.
#include "core/error.hpp"
#include "core/rng.hpp"
#include "par/comm.hpp"
#include "pipelines/solid_synthesis/appearance_space_cache.hpp"
#include "support/test_data.hpp"
#include "support/test_files.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>

namespace texsim::pipelines::solid_synthesis {
namespace {

constexpr const char* kExemplarHash = "0123456789abcdef";

/// Uniform random colours in [0, 1).
vol::ChannelGrid random_exemplar(vol::Dims dims, std::uint64_t seed) {
  vol::ChannelGrid grid(dims, 3);
  const CounterRng rng(seed, 0);
  for (std::size_t v = 0; v < grid.data().size(); ++v)
    grid.data()[v] = static_cast<float>(rng.uniform(v, 0));
  return grid;
}

bool same_bytes(const vol::ChannelGrid& a, const vol::ChannelGrid& b) {
  return a.dims() == b.dims() && a.channels() == b.channels() &&
         std::memcmp(a.data().data(), b.data().data(), a.data().size_bytes()) == 0;
}

template <class Matrix> bool same_bytes(const Matrix& a, const Matrix& b) {
  return a.rows() == b.rows() && a.cols() == b.cols() &&
         std::memcmp(a.data(), b.data(), static_cast<std::size_t>(a.size()) * sizeof(double)) == 0;
}

/// Every member equal bit for bit.
void expect_identical(const AppearanceSpace& loaded, const AppearanceSpace& built) {
  EXPECT_TRUE(same_bytes(loaded.colours, built.colours));
  EXPECT_EQ(loaded.periodic, built.periodic);
  ASSERT_EQ(loaded.stack.size(), built.stack.size());
  ASSERT_EQ(loaded.levels.size(), built.levels.size());
  for (std::size_t s = 0; s < built.levels.size(); ++s) {
    SCOPED_TRACE("level " + std::to_string(s));
    const AppearanceLevel& a = loaded.levels[s];
    const AppearanceLevel& b = built.levels[s];
    EXPECT_TRUE(same_bytes(loaded.stack[s], built.stack[s]));
    EXPECT_EQ(a.spacing, b.spacing);
    EXPECT_EQ(a.window, b.window);
    EXPECT_TRUE(same_bytes(a.features, b.features));
    EXPECT_TRUE(same_bytes(a.mean, b.mean));
    EXPECT_TRUE(same_bytes(a.basis, b.basis));
    EXPECT_EQ(std::memcmp(&a.retained_variance, &b.retained_variance, sizeof(double)), 0);
  }
}

std::string read_file(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

TEST(AppearanceSpaceCache, KeyNamesTheExemplarAndEveryOption) {
  const AppearanceOptions options{8, 5, ExemplarBorder::toroidal};
  const std::string key = appearance_cache_key(kExemplarHash, options);
  EXPECT_EQ(key, "0123456789abcdef-d8-w5-toroidal");
  EXPECT_NE(appearance_cache_key("0123456789abcdee", options), key);
  EXPECT_NE(appearance_cache_key(kExemplarHash, {4, 5, ExemplarBorder::toroidal}), key);
  EXPECT_NE(appearance_cache_key(kExemplarHash, {8, 3, ExemplarBorder::toroidal}), key);
  EXPECT_EQ(appearance_cache_key(kExemplarHash, {8, 5, ExemplarBorder::discard}),
            "0123456789abcdef-d8-w5-discard");
  EXPECT_THROW(appearance_cache_key("../../etc/passwd", options), Error);
  EXPECT_THROW(appearance_cache_key("0123456789ABCDEF", options), Error);
}

TEST(AppearanceSpaceCache, LoadedSpaceIsBitwiseTheBuiltOne) {
  const par::Comm comm = par::world();
  const auto dir = test::scratch_dir("appearance_space_cache_round_trip");
  const vol::ChannelGrid exemplar = random_exemplar({12, 10, 9}, 4);
  for (const ExemplarBorder border : {ExemplarBorder::toroidal, ExemplarBorder::discard}) {
    SCOPED_TRACE(border == ExemplarBorder::toroidal ? "toroidal" : "discard");
    const AppearanceOptions options{4, 3, border};
    const AppearanceSpace built = build_appearance_space(exemplar, options);
    const std::string key = appearance_cache_key(kExemplarHash, options);
    const auto file = dir / "cache" / ("appearance_" + key + ".h5"); // no directory yet
    EXPECT_FALSE(load_appearance_space(comm, file, key).has_value()) << "no file yet";
    save_appearance_space(comm, file, key, built);
    EXPECT_TRUE(test::temporary_files_under(dir).empty());
    comm.barrier(); // before rank 0 writes the next file

    const auto loaded = load_appearance_space(comm, file, key);
    ASSERT_TRUE(loaded.has_value());
    expect_identical(*loaded, built);
  }
}

TEST(AppearanceSpaceCache, ForeignDamagedOrUnwritableFilesAreNotUsed) {
  const par::Comm comm = par::world();
  const auto dir = test::scratch_dir("appearance_space_cache_refusals");
  const auto file = dir / "space.h5";
  const AppearanceOptions options{4, 3, ExemplarBorder::toroidal};
  const AppearanceSpace built = build_appearance_space(random_exemplar({10, 9, 8}, 5), options);
  const std::string key = appearance_cache_key(kExemplarHash, options);
  save_appearance_space(comm, file, key, built);

  EXPECT_FALSE(load_appearance_space(comm, file, appearance_cache_key("00000000000000ff", options))
                   .has_value())
      << "another exemplar";
  EXPECT_FALSE(load_appearance_space(
                   comm, file, appearance_cache_key(kExemplarHash, {4, 3, ExemplarBorder::discard}))
                   .has_value())
      << "another border";
  EXPECT_THROW(
      save_appearance_space(
          comm, file, appearance_cache_key(kExemplarHash, {5, 3, ExemplarBorder::toroidal}), built),
      Error)
      << "a space that does not fit its key";

  // One flipped bit inside the finest level's features, in its first plane (read by rank 0) or
  // its last (read by the last rank): the Fletcher-32 checksum catches it, and every rank
  // recomputes.
  const std::string intact = read_file(file);
  const auto features = built.levels.front().features.data();
  for (const std::size_t offset : {std::size_t{0}, features.size_bytes() - 64}) {
    if (comm.is_root()) {
      const std::string_view needle(reinterpret_cast<const char*>(features.data()) + offset, 64);
      const auto at = intact.find(needle);
      EXPECT_NE(at, std::string::npos) << "features not stored verbatim";
      test::Bytes bytes(intact.begin(), intact.end());
      if (at != std::string::npos)
        bytes[at + 40] ^= 0x10;
      test::write_bytes(file, bytes);
    }
    comm.barrier();
    EXPECT_FALSE(load_appearance_space(comm, file, key).has_value()) << "flipped bit at " << offset;
  }

  // Truncated and foreign files are not used; saving again replaces them.
  if (comm.is_root())
    test::write_bytes(file, test::Bytes(intact.begin(), intact.begin() + intact.size() / 2));
  comm.barrier();
  EXPECT_FALSE(load_appearance_space(comm, file, key).has_value()) << "truncated file";
  if (comm.is_root())
    test::write_bytes(file, test::Bytes(4096, 0x5a));
  comm.barrier();
  EXPECT_FALSE(load_appearance_space(comm, file, key).has_value()) << "not an HDF5 file";
  save_appearance_space(comm, file, key, built);
  const auto again = load_appearance_space(comm, file, key);
  ASSERT_TRUE(again.has_value());
  expect_identical(*again, built);

  // A cache that cannot be written (its directory is a file) costs the next run, not this one.
  const auto blocked = file / "space.h5";
  EXPECT_NO_THROW(save_appearance_space(comm, blocked, key, built));
  EXPECT_FALSE(load_appearance_space(comm, blocked, key).has_value());
}

} // namespace
} // namespace texsim::pipelines::solid_synthesis
