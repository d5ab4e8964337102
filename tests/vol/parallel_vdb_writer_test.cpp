// A volume split in z over the ranks, written as one .vdb by all of them at once, is the file
// OpenVDB's own writer makes of the same dense tree (uncompressed, zip or Blosc, with its default
// grid statistics) byte for byte but the UUID, for smooth and incompressible values; the bytes
// do not depend on how the planes are split; the UUID follows
// the content; read_vdb gives the volume back; and planes that do not tile the volume are refused
// on every rank with the file left as it was. The layout's leaf order and topology are OpenVDB's
// for volumes wider than one upper node (4096 voxels).
#include "core/error.hpp"
#include "par/comm.hpp"
#include "support/test_data.hpp"
#include "vol/channel_grid.hpp"
#include "vol/parallel_vdb_writer.hpp"
#include "vol/vdb_dense_layout.hpp"
#include "vol/vdb_grid_description.hpp"
#include "vol/vdb_io.hpp"

#include <gtest/gtest.h>
#include <mpi.h>

#include <openvdb/io/Archive.h>
#include <openvdb/io/File.h>
#include <openvdb/io/io.h>
#include <openvdb/openvdb.h>

#include <fstream>
#include <iterator>
#include <sstream>
#include <string>
#include <variant>

namespace texsim::vol {
namespace {
namespace fs = std::filesystem;

constexpr std::size_t kUuidAt = DenseVdbLayout::kUuidAt, kUuidLength = 36;

float value(int i, int j, int k, int c) {
  // Some voxels are exactly 0, the background: they must stay active.
  return (i + j + k) % 5 == 0 ? 0.0f : 0.01f * static_cast<float>(i + 7 * j + 31 * k) + 0.5f * c;
}

/// Bits no compressor shrinks: zlib and Blosc store such leaves raw, with a negative count.
float noise(int i, int j, int k, int c) {
  std::uint64_t x = (std::uint64_t(i) << 40) ^ (std::uint64_t(j) << 20) ^ std::uint64_t(k) ^
                    (std::uint64_t(c) << 60);
  x ^= x >> 33;
  x *= 0xff51afd7ed558ccdULL;
  x ^= x >> 33;
  x *= 0xc4ceb9fe1a85ec53ULL;
  x ^= x >> 33;
  return static_cast<float>(x >> 40) / static_cast<float>(1 << 24);
}

ChannelGrid volume(Dims dims, int channels, float (*f)(int, int, int, int) = value) {
  ChannelGrid grid(dims, channels);
  for (int k = 0; k < dims.nz; ++k)
    for (int j = 0; j < dims.ny; ++j)
      for (int i = 0; i < dims.nx; ++i)
        for (int c = 0; c < channels; ++c)
          grid.data()[grid.index(i, j, k) * std::size_t(channels) + std::size_t(c)] = f(i, j, k, c);
  return grid;
}

/// The flags the layout gives OpenVDB for `compression`.
std::uint32_t openvdb_flags(VdbCompression compression) {
  return DenseVdbLayout({1, 1, 1}, 1, compression).openvdb_flags();
}

const char* name_of(VdbCompression compression) {
  return compression == VdbCompression::none
             ? "none"
             : (compression == VdbCompression::zip ? "zip" : "blosc");
}

/// Planes [first, end) of `nz` for this rank when plane z goes to rank z * size / nz rounded as
/// `shift` says (0: even shares; larger: more planes to the last ranks).
std::array<int, 2> share(const par::Comm& comm, int nz, int shift) {
  const auto start = [&](int rank) {
    return rank == 0 ? 0 : std::min(nz, (nz * rank) / comm.size + shift);
  };
  return {start(comm.rank), comm.rank + 1 == comm.size ? nz : start(comm.rank + 1)};
}

void write_share(const par::Comm& comm, const fs::path& path, const ChannelGrid& grid,
                 std::array<int, 2> planes, VdbCompression compression = VdbCompression::none) {
  const std::size_t plane =
      std::size_t(grid.dims().nx) * std::size_t(grid.dims().ny) * std::size_t(grid.channels());
  const auto values = grid.data();
  write_parallel_vdb(comm, path, grid.dims(), grid.channels(), planes[0],
                     std::vector<float>(values.begin() + std::ptrdiff_t(planes[0] * plane),
                                        values.begin() + std::ptrdiff_t(planes[1] * plane)),
                     "g", compression);
}

std::string bytes_of(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), {}};
}

/// OpenVDB's own file of the dense tree: a leaf for every 8^3 block, every voxel set active.
template <class Grid>
void write_reference(const fs::path& path, const ChannelGrid& grid, VdbCompression compression) {
  initialize_openvdb();
  auto vdb = Grid::create();
  auto accessor = vdb->getAccessor();
  const Dims d = grid.dims();
  for (int k = 0; k < d.nz; ++k)
    for (int j = 0; j < d.ny; ++j)
      for (int i = 0; i < d.nx; ++i) {
        const auto v = grid.voxel(grid.index(i, j, k));
        if constexpr (std::is_same_v<typename Grid::ValueType, float>)
          accessor.setValueOn(openvdb::Coord(i, j, k), v[0]);
        else
          accessor.setValueOn(openvdb::Coord(i, j, k), openvdb::Vec3s(v[0], v[1], v[2]));
      }
  describe_dense_grid(*vdb, d, {1.0, 1.0, 1.0}, {0.0, 0.0, 0.0}, "g");
  openvdb::io::File file(path.string());
  file.setCompression(openvdb_flags(compression));
  file.write(openvdb::GridCPtrVec{vdb});
  file.close();
}

TEST(DenseVdbLayout, BloscIsOpenVdbsDefaultCompression) {
  EXPECT_EQ(openvdb_flags(VdbCompression::blosc), openvdb::io::Archive::DEFAULT_COMPRESSION_FLAGS);
  EXPECT_EQ(openvdb_flags(VdbCompression::zip),
            openvdb::io::COMPRESS_ZIP | openvdb::io::COMPRESS_ACTIVE_MASK);
  EXPECT_EQ(openvdb_flags(VdbCompression::none), openvdb::io::COMPRESS_NONE);
}

TEST(ParallelVdb, IsOpenVdbsOwnFileButTheUuid) {
  const par::Comm comm = par::world();
  const fs::path dir = test::scratch_dir("parallel_vdb_reference");
  // Two lower nodes along x (140 > 128), partial leaves on every axis, one-plane volumes;
  // smooth values that compress and noise that does not.
  struct Case {
    Dims dims;
    float (*values)(int, int, int, int);
  };
  for (const Case c : {Case{{20, 13, 9}, value}, Case{{140, 9, 17}, value}, Case{{5, 3, 1}, value},
                       Case{{20, 13, 9}, noise}})
    for (const int channels : {1, 3})
      for (const VdbCompression compression :
           {VdbCompression::none, VdbCompression::zip, VdbCompression::blosc}) {
        const ChannelGrid grid = volume(c.dims, channels, c.values);
        const std::string name = std::to_string(c.dims.nx) + "_" + std::to_string(channels) + "_" +
                                 name_of(compression) + (c.values == noise ? "_noise" : "");
        write_share(comm, dir / (name + ".vdb"), grid, share(comm, c.dims.nz, 0), compression);
        if (!comm.is_root())
          continue;
        if (channels == 1)
          write_reference<openvdb::FloatGrid>(dir / (name + "_openvdb.vdb"), grid, compression);
        else
          write_reference<openvdb::Vec3SGrid>(dir / (name + "_openvdb.vdb"), grid, compression);
        std::string ours = bytes_of(dir / (name + ".vdb"));
        std::string reference = bytes_of(dir / (name + "_openvdb.vdb"));
        // Only rank 0 checks: a fatal assertion here would leave the other ranks waiting.
        EXPECT_EQ(ours.size(), reference.size()) << name;
        ours.replace(kUuidAt, kUuidLength, kUuidLength, '-');
        reference.replace(kUuidAt, kUuidLength, kUuidLength, '-');
        EXPECT_TRUE(ours == reference) << name << ": the files differ";

        const AnyGrid back = read_vdb(dir / (name + ".vdb"), "g");
        const std::span<const float> expected = grid.data();
        if (channels == 1) {
          const auto values = std::get<ScalarGrid>(back).data();
          EXPECT_TRUE(std::equal(values.begin(), values.end(), expected.begin())) << name;
        } else {
          const auto values = std::get<RgbGrid>(back).data();
          EXPECT_EQ(values.size() * 3, expected.size());
          std::size_t differing = 0;
          for (std::size_t v = 0; v < values.size() && 3 * v + 2 < expected.size(); ++v)
            differing += !(values[v].r == expected[3 * v] && values[v].g == expected[3 * v + 1] &&
                           values[v].b == expected[3 * v + 2]);
          EXPECT_EQ(differing, 0u) << name;
        }
      }
}

TEST(ParallelVdb, BytesDoNotDependOnTheSplitAndTheUuidFollowsTheContent) {
  const par::Comm comm = par::world();
  const fs::path dir = test::scratch_dir("parallel_vdb_split");
  for (const VdbCompression compression : {VdbCompression::none, VdbCompression::blosc}) {
    ChannelGrid grid = volume(Dims{12, 10, 23}, 3);
    write_share(comm, dir / "even.vdb", grid, share(comm, 23, 0), compression);
    write_share(comm, dir / "skewed.vdb", grid, share(comm, 23, 5), compression);
    write_share(comm, dir / "last.vdb", grid, share(comm, 23, 23), compression);
    grid.data()[grid.data().size() / 2] += 1.0f;
    write_share(comm, dir / "changed.vdb", grid, share(comm, 23, 0), compression);
    if (comm.is_root()) {
      const std::string even = bytes_of(dir / "even.vdb");
      EXPECT_TRUE(even == bytes_of(dir / "skewed.vdb")) << name_of(compression);
      EXPECT_TRUE(even == bytes_of(dir / "last.vdb")) << name_of(compression);
      const std::string changed = bytes_of(dir / "changed.vdb");
      EXPECT_NE(even.substr(kUuidAt, kUuidLength), changed.substr(kUuidAt, kUuidLength))
          << name_of(compression) << ": one voxel changed, the UUID must too";
    }
    comm.barrier();
  }
}

TEST(ParallelVdb, PlanesThatDoNotTileAreRefusedOnEveryRankAndTheFileKept) {
  const par::Comm comm = par::world();
  const fs::path dir = test::scratch_dir("parallel_vdb_refused");
  const ChannelGrid grid = volume(Dims{4, 4, 6}, 1);
  write_share(comm, dir / "kept.vdb", grid, share(comm, 6, 0));
  std::string before;
  if (comm.is_root())
    before = bytes_of(dir / "kept.vdb");
  comm.barrier();
  // Every rank claims all planes: they overlap from 2 ranks on; at 1 rank a plane is missing.
  const std::array<int, 2> overlapping{0, comm.size == 1 ? 5 : 6};
  EXPECT_THROW(write_share(comm, dir / "kept.vdb", grid, overlapping), Error);
  if (comm.is_root()) {
    EXPECT_TRUE(bytes_of(dir / "kept.vdb") == before);
  }
}

TEST(DenseVdbLayout, LeafOrderTopologyAndMemoryAreOpenVdbsBeyondOneUpperNode) {
  initialize_openvdb();
  for (const Dims dims : {Dims{4100, 1, 9}, Dims{9, 4105, 3}, Dims{3, 9, 4200}}) {
    openvdb::FloatTree tree(0.0f);
    for (int k = 0; k < dims.nz; ++k)
      for (int j = 0; j < dims.ny; ++j)
        for (int i = 0; i < dims.nx; ++i)
          tree.setValueOn(openvdb::Coord(i, j, k), 1.0f);
    const DenseVdbLayout layout(dims, 1);
    ASSERT_EQ(layout.leaf_count(), std::int64_t(tree.leafCount()));
    std::int64_t order = 0;
    for (auto leaf = tree.cbeginLeaf(); leaf; ++leaf, ++order) {
      const openvdb::Coord origin = leaf->origin();
      ASSERT_EQ(layout.leaf_order({origin.x() / 8, origin.y() / 8, origin.z() / 8}), order)
          << "leaf at " << origin;
    }
    for (const VdbCompression compression : {VdbCompression::none, VdbCompression::blosc}) {
      std::ostringstream reference(std::ios::binary);
      openvdb::io::setDataCompression(reference, openvdb_flags(compression));
      tree.writeTopology(reference);
      const DenseVdbLayout compressed(dims, 1, compression);
      std::string ours;
      compressed.write_topology([&](std::string_view bytes) { ours += bytes; });
      EXPECT_EQ(ours.size(), compressed.topology_bytes());
      EXPECT_TRUE(ours == reference.str())
          << dims.nx << " x " << dims.ny << " x " << dims.nz << " " << name_of(compression);
    }
    EXPECT_EQ(layout.tree_memory_bytes(), std::int64_t(tree.memUsage()));
    EXPECT_EQ(
        DenseVdbLayout(dims, 3).tree_memory_bytes(),
        std::int64_t(
            openvdb::Vec3STree(tree, openvdb::Vec3s(0.0f), openvdb::TopologyCopy()).memUsage()));
  }
}

} // namespace
} // namespace texsim::vol
