// Checkpoint store: bit-exact round trips across different splits and rank counts, checksums
// independent of the split, refusal of corrupt, truncated and foreign checkpoints on every rank,
// "latest" fallback, pruning and atomic commit.
#include "core/atomic_output.hpp"
#include "io/checkpoint_format.hpp"
#include "io/checkpoint_store.hpp"
#include "par/comm.hpp"
#include "par/positional_checksum.hpp"
#include "support/test_data.hpp"

#include <gtest/gtest.h>
#include <hdf5.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <limits>

namespace texsim::io {
namespace {

struct Block {
  std::uint64_t offset;
  std::uint64_t count;
};

/// Rank `rank`'s share of `total` elements, proportional to `weights` (one per rank).
Block weighted_block(std::uint64_t total, int rank, const std::vector<std::uint64_t>& weights) {
  std::uint64_t sum = 0, before = 0;
  for (std::size_t r = 0; r < weights.size(); ++r) {
    sum += weights[r];
    if (static_cast<int>(r) < rank)
      before += weights[r];
  }
  const std::uint64_t begin = total * before / sum;
  const std::uint64_t end = total * (before + weights[rank]) / sum;
  return {begin, end - begin};
}

Block even_block(std::uint64_t total, const par::Comm& comm) {
  return weighted_block(total, comm.rank, std::vector<std::uint64_t>(comm.size, 1));
}

/// A deliberately lopsided split: rank r gets a share proportional to (size - r)^2, and rank 1
/// (if any) gets nothing.
Block uneven_block(std::uint64_t total, const par::Comm& comm) {
  std::vector<std::uint64_t> weights;
  for (int r = 0; r < comm.size; ++r)
    weights.push_back(r == 1 ? 0 : static_cast<std::uint64_t>((comm.size - r) * (comm.size - r)));
  return weighted_block(total, comm.rank, weights);
}

/// Global reference arrays, with awkward values (negative zero, NaN, extremes).
template <class T> std::vector<T> reference(std::uint64_t scalars) {
  std::vector<T> values(scalars);
  for (std::uint64_t i = 0; i < scalars; ++i) {
    if constexpr (std::is_floating_point_v<T>)
      values[i] = static_cast<T>(std::sin(0.37 * i) * 1e3);
    else
      values[i] = static_cast<T>(i * 2654435761ULL);
  }
  if constexpr (std::is_floating_point_v<T>) {
    values[0] = -0.0;
    values[1] = std::numeric_limits<T>::quiet_NaN();
    values[2] = std::numeric_limits<T>::denorm_min();
  } else {
    values[0] = std::numeric_limits<T>::max();
    values[1] = std::numeric_limits<T>::min();
  }
  return values;
}

constexpr std::uint64_t elements = 1003;

template <class T>
void write_reference(CheckpointWriter& writer, const std::string& name, int components,
                     Block block) {
  const auto all = reference<T>(elements * components);
  writer.write<T>(
      name, std::span<const T>(all).subspan(block.offset * components, block.count * components),
      block.offset, elements, components);
}

template <class T>
void expect_reference(const CheckpointReader& reader, const std::string& name, int components,
                      Block block) {
  ASSERT_EQ(reader.global_count(name), elements);
  ASSERT_EQ(reader.components(name), components);
  std::vector<T> local(block.count * components);
  reader.read<T>(name, std::span<T>(local), block.offset, block.count);
  const auto all = reference<T>(elements * components);
  EXPECT_EQ(
      std::memcmp(local.data(), all.data() + block.offset * components, local.size() * sizeof(T)),
      0)
      << name << " differs bitwise";
}

/// Calls `visit.template operator()<T>(name, components)` for each dataset the tests store: every
/// scalar type, with one and three components.
template <class Visit> void for_all_types(Visit&& visit) {
  visit.template operator()<double>("f64", 1);
  visit.template operator()<double>("f64x3", 3);
  visit.template operator()<float>("f32", 1);
  visit.template operator()<std::int32_t>("i32", 1);
  visit.template operator()<std::int64_t>("i64x3", 3);
  visit.template operator()<std::uint8_t>("u8", 1);
  visit.template operator()<std::uint64_t>("u64", 1);
}

void write_all_types(CheckpointWriter& writer, Block block) {
  for_all_types([&]<class T>(const std::string& name, int components) {
    write_reference<T>(writer, name, components, block);
  });
}

void expect_all_types(const CheckpointReader& reader, Block block) {
  for_all_types([&]<class T>(const std::string& name, int components) {
    expect_reference<T>(reader, name, components, block);
  });
}

std::filesystem::path write_checkpoint(const CheckpointStore& store, std::int64_t step,
                                       const par::Comm& comm) {
  auto writer = store.begin(step);
  write_all_types(writer, even_block(elements, comm));
  writer.set_attribute("time", 0.125 * step);
  writer.set_attribute("seed", std::uint64_t{0xFEDCBA9876543210ULL});
  writer.set_attribute("iterations", std::int64_t{-42});
  writer.set_attribute("pipeline", "solid_synthesis");
  return writer.commit();
}

/// Flips bytes in the middle of dataset `name`'s data on disk. Rank 0 only.
void corrupt_dataset(const std::filesystem::path& path, const std::string& name) {
  const hid_t file = H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  ASSERT_GE(file, 0);
  const hid_t dataset = H5Dopen2(file, name.c_str(), H5P_DEFAULT);
  const haddr_t offset = H5Dget_offset(dataset);
  const hsize_t size = H5Dget_storage_size(dataset);
  H5Dclose(dataset);
  H5Fclose(file);
  ASSERT_NE(offset, HADDR_UNDEF);
  std::fstream stream(path, std::ios::in | std::ios::out | std::ios::binary);
  stream.seekg(static_cast<std::streamoff>(offset + size / 2));
  char bytes[4];
  stream.read(bytes, 4);
  for (char& byte : bytes)
    byte = static_cast<char>(~byte);
  stream.seekp(static_cast<std::streamoff>(offset + size / 2));
  stream.write(bytes, 4);
}

std::uint64_t stored_checksum(const std::filesystem::path& path, const std::string& name) {
  const hid_t file = H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  const hid_t dataset = H5Dopen2(file, name.c_str(), H5P_DEFAULT);
  const hid_t attribute = H5Aopen(dataset, checksum_attribute, H5P_DEFAULT);
  std::uint64_t value = 0;
  H5Aread(attribute, H5T_NATIVE_UINT64, &value);
  H5Aclose(attribute);
  H5Dclose(dataset);
  H5Fclose(file);
  return value;
}

template <class Work> void expect_input_error(Work work, const std::vector<std::string>& parts) {
  try {
    work();
    ADD_FAILURE() << "no InputError";
  } catch (const InputError& e) {
    for (const auto& part : parts)
      EXPECT_NE(std::string(e.what()).find(part), std::string::npos)
          << "message '" << e.what() << "' lacks '" << part << "'";
  }
}

TEST(CheckpointStore, RoundTripIsBitExactWithADifferentSplit) {
  const auto comm = par::world();
  const CheckpointStore store(comm, test::scratch_dir("ckpt_roundtrip"), "hash-a", 3);
  const auto path = write_checkpoint(store, 100, comm);
  EXPECT_EQ(path.filename(), "step_000000100.h5");

  const auto reader = store.open(path);
  EXPECT_EQ(reader.step(), 100);
  expect_all_types(reader, uneven_block(elements, comm));
  EXPECT_EQ(reader.attribute_double("time"), 12.5);
  EXPECT_EQ(reader.attribute_uint64("seed"), 0xFEDCBA9876543210ULL);
  EXPECT_EQ(reader.attribute_int64("iterations"), -42);
  EXPECT_EQ(reader.attribute_string("pipeline"), "solid_synthesis");
  EXPECT_FALSE(reader.has_attribute("absent"));
  EXPECT_THROW(reader.attribute_int64("time"), InputError);
  EXPECT_THROW(reader.global_count("absent"), InputError);
}

TEST(CheckpointStore, ChecksumDoesNotDependOnTheSplit) {
  const auto values = reference<double>(300);
  const std::uint64_t whole = par::checksum_block(values.data(), values.size(), 8, 0);
  const std::uint64_t split = par::checksum_block(values.data(), 117, 8, 0) +
                              par::checksum_block(values.data() + 117, 183, 8, 117);
  EXPECT_EQ(whole, split);
  auto swapped = values;
  std::swap(swapped[10], swapped[20]);
  EXPECT_NE(par::checksum_block(swapped.data(), swapped.size(), 8, 0), whole)
      << "moving values must change the checksum";

  // The same data written by all ranks and by rank 0 alone carries the same checksums.
  const auto comm = par::world();
  const auto all_ranks = test::scratch_dir("ckpt_checksum_all");
  const auto one_rank = test::scratch_dir("ckpt_checksum_one");
  const auto path_all = write_checkpoint(CheckpointStore(comm, all_ranks, "h", 1), 1, comm);
  if (comm.is_root()) {
    const par::Comm self{MPI_COMM_SELF, 0, 1};
    const auto path_one = write_checkpoint(CheckpointStore(self, one_rank, "h", 1), 1, self);
    for (const char* name : {"f64", "f64x3", "f32", "i32", "i64x3", "u8", "u64"})
      EXPECT_EQ(stored_checksum(path_all, name), stored_checksum(path_one, name)) << name;
  }
  comm.barrier();
}

TEST(CheckpointStore, CorruptDataIsRefusedOnEveryRank) {
  const auto comm = par::world();
  const CheckpointStore store(comm, test::scratch_dir("ckpt_corrupt"), "hash-a", 3);
  const auto path = write_checkpoint(store, 7, comm);
  if (comm.is_root())
    corrupt_dataset(path, "f64x3");
  comm.barrier();
  expect_input_error([&] { store.open(path); }, {path.string(), "corrupt checkpoint", "f64x3"});
}

TEST(CheckpointStore, TruncatedFileIsRefused) {
  const auto comm = par::world();
  const CheckpointStore store(comm, test::scratch_dir("ckpt_truncated"), "hash-a", 3);
  const auto path = write_checkpoint(store, 7, comm);
  if (comm.is_root())
    std::filesystem::resize_file(path, std::filesystem::file_size(path) / 2);
  comm.barrier();
  expect_input_error([&] { store.open(path); }, {path.string(), "corrupt checkpoint"});
  expect_input_error([&] { store.open(path.parent_path() / "step_000000001.h5"); },
                     {"step_000000001.h5", "no such checkpoint"});
}

TEST(CheckpointStore, LatestFallsBackToThePreviousGoodCheckpoint) {
  const auto comm = par::world();
  const CheckpointStore store(comm, test::scratch_dir("ckpt_latest"), "hash-a", 5);
  write_checkpoint(store, 10, comm);
  const auto good = write_checkpoint(store, 20, comm);
  const auto bad = write_checkpoint(store, 30, comm);
  EXPECT_EQ(store.resolve("latest").reader.path(), bad);
  if (comm.is_root())
    corrupt_dataset(bad, "u8");
  comm.barrier();
  const auto resolved = store.resolve("latest");
  EXPECT_EQ(resolved.reader.path(), good);
  ASSERT_EQ(resolved.skipped.size(), 1u);
  EXPECT_EQ(resolved.skipped[0].path, bad);
  EXPECT_NE(resolved.skipped[0].reason.find("corrupt checkpoint"), std::string::npos);
  EXPECT_EQ(store.resolve(good.string()).reader.path(), good);
  EXPECT_EQ(resolved.reader.step(), 20);
}

TEST(CheckpointStore, LatestInAnEmptyDirectoryIsAnInputError) {
  const auto comm = par::world();
  const auto dir = test::scratch_dir("ckpt_empty");
  const CheckpointStore store(comm, dir, "hash-a", 1);
  expect_input_error([&] { store.resolve("latest"); }, {dir.string(), "no usable checkpoint"});
}

TEST(CheckpointStore, KeepsTheNewestAndLeavesNoTemporaryFile) {
  const auto comm = par::world();
  const auto dir = test::scratch_dir("ckpt_prune");
  const CheckpointStore store(comm, dir, "hash-a", 2);
  for (std::int64_t step = 1; step <= 4; ++step)
    write_checkpoint(store, step, comm);
  EXPECT_EQ(store.steps(), (std::vector<std::int64_t>{3, 4}));
  // A restarted run rewriting step 3 discards the stale later step 4.
  write_checkpoint(store, 3, comm);
  EXPECT_EQ(store.steps(), (std::vector<std::int64_t>{3}));
  if (comm.is_root()) {
    for (const auto& entry : std::filesystem::directory_iterator(dir))
      EXPECT_TRUE(checkpoint_step_of(entry.path().filename().string()))
          << "unexpected file " << entry.path();
  }
  comm.barrier();
}

TEST(CheckpointStore, AnUncommittedCheckpointIsNeverReadAndIsRemovedByTheNextRun) {
  const auto comm = par::world();
  const auto dir = test::scratch_dir("ckpt_uncommitted");
  {
    const CheckpointStore store(comm, dir, "hash-a", 2);
    write_checkpoint(store, 1, comm);
    // A job killed while writing step 2: its temporary file stays, under rank 0's pid.
    auto writer = store.begin(2);
    write_all_types(writer, even_block(elements, comm));
    EXPECT_EQ(store.steps(), (std::vector<std::int64_t>{1}));
  }
  if (comm.is_root()) {
    std::vector<std::string> names;
    for (const auto& entry : std::filesystem::directory_iterator(dir))
      names.push_back(entry.path().filename().string());
    std::sort(names.begin(), names.end());
    ASSERT_EQ(names.size(), 2u);
    EXPECT_EQ(names[0], "step_000000001.h5");
    EXPECT_EQ(final_name_of_temporary(names[1]), "step_000000002.h5") << names[1];
  }
  // The restarted job resolves step 1 and clears the leftover.
  const CheckpointStore restarted(comm, dir, "hash-a", 2);
  EXPECT_EQ(restarted.resolve("latest").reader.step(), 1);
  if (comm.is_root()) {
    for (const auto& entry : std::filesystem::directory_iterator(dir))
      EXPECT_TRUE(checkpoint_step_of(entry.path().filename().string()))
          << "unexpected file " << entry.path();
  }
  comm.barrier();
}

TEST(CheckpointStore, AnotherConfigurationIsRefusedNamingTheFile) {
  const auto comm = par::world();
  const auto dir = test::scratch_dir("ckpt_config");
  const auto path = write_checkpoint(CheckpointStore(comm, dir, "aaaa", 2), 5, comm);
  expect_input_error(
      [&] { CheckpointStore(comm, dir, "bbbb", 2); },
      {path.string(), "written by a different configuration", "config hash aaaa", "this run bbbb"});
  const CheckpointStore other(comm, test::scratch_dir("ckpt_config_other"), "bbbb", 2);
  expect_input_error([&] { other.open(path); },
                     {path.string(), "written by a different configuration"});
  expect_input_error([&] { other.resolve(path.string()); }, {path.string()});
}

TEST(CheckpointStore, BlocksThatDoNotTileAreAnErrorOnEveryRank) {
  const auto comm = par::world();
  const CheckpointStore store(comm, test::scratch_dir("ckpt_tiling"), "hash-a", 1);
  auto writer = store.begin(1);
  const std::vector<double> local(10, 1.0);
  // Every rank claims elements [0, 10) of a dataset of 10 * size elements: overlap and a gap.
  EXPECT_THROW(writer.write<double>("x", local, 0, 10 * comm.size + 1), Error);
  writer.write<double>("y", local, 10 * comm.rank, 10 * comm.size);
  writer.commit();
}

/// Set by the io_checkpoint_cross_* ctest pair: written at 3 ranks, read at 2.
std::filesystem::path cross_rank_dir() {
  const char* dir = std::getenv("TEXSIM_IO_CROSS_RANK_DIR");
  return dir ? std::filesystem::path(dir) : std::filesystem::path();
}

TEST(CrossRankCount, WriteAtThisRankCount) {
  if (cross_rank_dir().empty())
    GTEST_SKIP() << "run by the io_checkpoint_cross_write ctest";
  const auto comm = par::world();
  if (comm.is_root())
    std::filesystem::remove_all(cross_rank_dir());
  comm.barrier();
  const CheckpointStore store(comm, cross_rank_dir(), "cross", 1);
  write_checkpoint(store, 3, comm);
}

TEST(CrossRankCount, ReadAtThisRankCount) {
  if (cross_rank_dir().empty())
    GTEST_SKIP() << "run by the io_checkpoint_cross_read ctest";
  const auto comm = par::world();
  const CheckpointStore store(comm, cross_rank_dir(), "cross", 1);
  const auto reader = store.resolve("latest").reader;
  EXPECT_EQ(reader.step(), 3);
  expect_all_types(reader, uneven_block(elements, comm));
  expect_all_types(reader, even_block(elements, comm));
}

} // namespace
} // namespace texsim::io
