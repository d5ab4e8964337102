#pragma once
/// A dense volume's .vdb file laid out in advance, so that ranks can write its parts at once
/// (vol/parallel_vdb_writer.hpp) without any rank building the OpenVDB tree.
///
/// The volume [0, nx) x [0, ny) x [0, nz), spacing 1 and origin 0, is stored as OpenVDB's
/// standard 5-4-3 tree (a FloatGrid for 1 channel, a Vec3SGrid for 3) with a leaf for every
/// 8^3 block that meets the volume, every voxel of the volume active and the rest inactive and 0,
/// no tiles, written uncompressed (COMPRESS_NONE). Every leaf record then has the same size and
/// its place in the file follows from its block coordinates alone. The bytes are those
/// openvdb::io::File writes for that tree with compression off and its default grid statistics
/// (tests/vol/parallel_vdb_writer_test.cpp compares them), except the UUID, which here is given.
///
/// File: header | grid head (descriptor, metadata, transform) | topology | leaf records.
#include "vol/dense_grid.hpp"

#include <array>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <span>
#include <string>
#include <string_view>

namespace texsim::vol {

class DenseVdbLayout {
public:
  static constexpr int kLeafDim = 8;
  /// Where the 36-character UUID sits in the file: after the magic number, three versions and
  /// the grid-offsets flag.
  static constexpr std::size_t kUuidAt = 21;

  /// A volume of `dims` voxels of `channels` (1 or 3) floats.
  DenseVdbLayout(Dims dims, int channels);

  /// Leaf blocks along each axis, and in all.
  std::array<int, 3> leaf_blocks() const { return blocks_; }
  std::int64_t leaf_count() const;
  /// Bytes of one leaf record: value mask, OpenVDB's per-node metadata byte, 512 values.
  std::size_t leaf_record_bytes() const;
  /// The place of leaf block (bx, by, bz) among the leaf records: OpenVDB's depth-first order
  /// (root children, then internal children, then leaves, each x slowest and z fastest).
  std::int64_t leaf_order(std::array<int, 3> block) const;

  /// The file from its start through the transform, for the grid named `grid_name` with
  /// texsim's dense-grid metadata (vol/vdb_io.hpp) and `uuid` (36 characters). Its stream
  /// positions say the topology follows at once and the leaf records after it.
  std::string head(const std::string& grid_name, std::string_view uuid) const;
  /// The bytes OpenVDB reports the loaded tree uses (openvdb::tools::memUsage), stored as the
  /// grid's `file_mem_bytes` statistic.
  std::int64_t tree_memory_bytes() const;
  /// Bytes of the topology (the tree's structure without leaf values).
  std::uint64_t topology_bytes() const;
  /// Emits the topology to `sink` a node of 128^3 voxels at a time, so its writer never holds
  /// more than one such node's part.
  void write_topology(const std::function<void(std::string_view)>& sink) const;

  /// Writes leaf block `block`'s record into `record` (leaf_record_bytes() long). `layer` holds
  /// the block's planes z = 8 bz .. min(8 bz + 8, nz) - 1, whole x-y planes one after the other,
  /// x fastest, `channels` floats per voxel.
  void write_leaf_record(std::span<std::byte> record, std::array<int, 3> block,
                         std::span<const float> layer) const;

private:
  Dims dims_;
  int channels_;
  std::array<int, 3> blocks_;
};

} // namespace texsim::vol
