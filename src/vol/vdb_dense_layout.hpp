#pragma once
/// A dense volume's .vdb file laid out in advance, so that ranks can write its parts at once
/// (vol/parallel_vdb_writer.hpp) without any rank building the OpenVDB tree.
///
/// The volume [0, nx) x [0, ny) x [0, nz), spacing 1 and origin 0, is stored as OpenVDB's
/// standard 5-4-3 tree (a FloatGrid for 1 channel, a Vec3SGrid for 3) with a leaf for every
/// 8^3 block that meets the volume, every voxel of the volume active and the rest inactive and 0,
/// and no tiles. Each leaf record is made by OpenVDB (LeafNode::writeBuffers) with the chosen
/// compression; the layout lists where the leaves go, and the head holds what OpenVDB's writer
/// puts there, the delayed-load table of every leaf's stored size included. The bytes are those
/// openvdb::io::File writes for that tree with the same compression and its default grid
/// statistics (tests/vol/parallel_vdb_writer_test.cpp compares them), except the UUID, which
/// here is given.
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

/// How leaf values are stored: raw, or compressed as openvdb::io::File does by default (zlib or
/// Blosc-LZ4, with OpenVDB's active-mask flag; every voxel is active, so it drops nothing).
enum class VdbCompression { none, zip, blosc };

/// The file from its start through the grid's transform, and where the leaf records start (after
/// the topology that follows the head).
struct VdbHead {
  std::string bytes;
  std::uint64_t leaves_at = 0;
};

class DenseVdbLayout {
public:
  static constexpr int kLeafDim = 8;
  /// Where the 36-character UUID sits in the file: after the magic number, three versions and
  /// the grid-offsets flag.
  static constexpr std::size_t kUuidAt = 21;

  /// A volume of `dims` voxels of `channels` (1 or 3) floats.
  DenseVdbLayout(Dims dims, int channels, VdbCompression compression = VdbCompression::none);

  VdbCompression compression() const { return compression_; }
  /// OpenVDB's compression flags (openvdb::io::COMPRESS_*) for compression().
  std::uint32_t openvdb_flags() const;

  /// Leaf blocks along each axis, and in all.
  std::array<int, 3> leaf_blocks() const { return blocks_; }
  std::int64_t leaf_count() const;
  /// Bytes of one uncompressed leaf record: value mask, OpenVDB's per-node metadata byte, 512
  /// values. Compressed records differ in size (append_leaf_record tells).
  std::size_t uncompressed_leaf_record_bytes() const;
  /// The place of leaf block (bx, by, bz) among the leaf records: OpenVDB's depth-first order
  /// (root children, then internal children, then leaves, each x slowest and z fastest).
  std::int64_t leaf_order(std::array<int, 3> block) const;

  /// The file from its start through the transform, for the grid named `grid_name` with
  /// texsim's dense-grid metadata (vol/vdb_io.hpp) and `uuid` (36 characters). `value_bytes`:
  /// each leaf's stored-value bytes in leaf order, as append_leaf_record returns them (the
  /// delayed-load table of a compressed file; ignored when uncompressed); `records_bytes`: all
  /// leaf records. Its stream positions say the topology follows at once and the leaf records
  /// after it.
  VdbHead head(const std::string& grid_name, std::string_view uuid,
               std::span<const std::int64_t> value_bytes, std::uint64_t records_bytes) const;
  /// The bytes OpenVDB reports the loaded tree uses (openvdb::tools::memUsage), stored as the
  /// grid's `file_mem_bytes` statistic.
  std::int64_t tree_memory_bytes() const;
  /// Bytes of the topology (the tree's structure without leaf values).
  std::uint64_t topology_bytes() const;
  /// Emits the topology to `sink` a node of 128^3 voxels at a time, so its writer never holds
  /// more than one such node's part.
  void write_topology(const std::function<void(std::string_view)>& sink) const;

  /// Appends leaf block `block`'s record to `record`. `layer` holds the block's planes
  /// z = 8 bz .. min(8 bz + 8, nz) - 1, whole x-y planes one after the other, x fastest,
  /// `channels` floats per voxel. Returns the bytes of the record's stored values with their
  /// 8-byte count, as OpenVDB's delayed-load table lists them (0 when uncompressed).
  std::int64_t append_leaf_record(std::string& record, std::array<int, 3> block,
                                  std::span<const float> layer) const;

private:
  Dims dims_;
  int channels_;
  VdbCompression compression_;
  std::array<int, 3> blocks_;
};

} // namespace texsim::vol
