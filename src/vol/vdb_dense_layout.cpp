#include "vol/vdb_dense_layout.hpp"

#include "core/error.hpp"
#include "vol/vdb_grid_description.hpp"

#include <algorithm>
#include <limits>
#include <sstream>
#include <type_traits>
#include <vector>

#include <openvdb/io/Compression.h>
#include <openvdb/io/DelayedLoadMetadata.h>
#include <openvdb/io/GridDescriptor.h>
#include <openvdb/io/io.h>
#include <openvdb/openvdb.h>

namespace texsim::vol {
namespace {

using Root = openvdb::FloatTree::RootNodeType;
using Upper = Root::ChildNodeType;  // InternalNode of 32^3 children (4096^3 voxels)
using Lower = Upper::ChildNodeType; // InternalNode of 16^3 leaves (128^3 voxels)
constexpr std::int64_t kUpperDim = Upper::DIM, kLowerDim = Lower::DIM;
constexpr std::int64_t kLeafSide = DenseVdbLayout::kLeafDim;
static_assert(openvdb::FloatTree::LeafNodeType::DIM == kLeafSide &&
              openvdb::Vec3STree::RootNodeType::ChildNodeType::DIM == Upper::DIM);

std::int64_t ceil_div(std::int64_t a, std::int64_t b) {
  return (a + b - 1) / b;
}

void write_pod(std::ostream& os, const auto& value) {
  os.write(reinterpret_cast<const char*>(&value), sizeof(value));
}

/// The grid type OpenVDB stores `channels` floats a voxel as.
template <class F> decltype(auto) with_grid_type(int channels, F&& f) {
  if (channels == 1)
    return f(openvdb::FloatGrid{});
  return f(openvdb::Vec3SGrid{});
}

/// The statistics openvdb::io::File adds by default (GridBase::addStatsMetadata and the
/// compression), which tools read without loading the tree, for `dims` voxels, all active.
void add_statistics(openvdb::GridBase& grid, Dims dims, std::int64_t tree_memory_bytes,
                    std::uint32_t compression_flags) {
  grid.insertMeta(openvdb::GridBase::META_FILE_COMPRESSION,
                  openvdb::StringMetadata(openvdb::io::compressionToString(compression_flags)));
  grid.insertMeta(openvdb::GridBase::META_FILE_BBOX_MIN, openvdb::Vec3IMetadata({0, 0, 0}));
  grid.insertMeta(openvdb::GridBase::META_FILE_BBOX_MAX,
                  openvdb::Vec3IMetadata({dims.nx - 1, dims.ny - 1, dims.nz - 1}));
  grid.insertMeta(openvdb::GridBase::META_FILE_MEM_BYTES,
                  openvdb::Int64Metadata(tree_memory_bytes));
  grid.insertMeta(openvdb::GridBase::META_FILE_VOXEL_COUNT,
                  openvdb::Int64Metadata(std::int64_t(dims.nx) * dims.ny * dims.nz));
}

} // namespace

DenseVdbLayout::DenseVdbLayout(Dims dims, int channels, VdbCompression compression)
    : dims_(dims), channels_(channels), compression_(compression) {
  TEXSIM_VERIFY(channels == 1 || channels == 3,
                "a .vdb grid of " << channels << " channels, expected 1 or 3");
  TEXSIM_VERIFY(dims.nx > 0 && dims.ny > 0 && dims.nz > 0,
                "a .vdb of " << dims.nx << " x " << dims.ny << " x " << dims.nz << " voxels");
  blocks_ = {static_cast<int>(ceil_div(dims.nx, kLeafSide)),
             static_cast<int>(ceil_div(dims.ny, kLeafSide)),
             static_cast<int>(ceil_div(dims.nz, kLeafSide))};
}

std::int64_t DenseVdbLayout::leaf_count() const {
  return std::int64_t(blocks_[0]) * blocks_[1] * blocks_[2];
}

std::uint32_t DenseVdbLayout::openvdb_flags() const {
  switch (compression_) {
  case VdbCompression::zip:
    return openvdb::io::COMPRESS_ZIP | openvdb::io::COMPRESS_ACTIVE_MASK;
  case VdbCompression::blosc:
    return openvdb::io::COMPRESS_BLOSC | openvdb::io::COMPRESS_ACTIVE_MASK;
  case VdbCompression::none:
    break;
  }
  return openvdb::io::COMPRESS_NONE;
}

std::size_t DenseVdbLayout::uncompressed_leaf_record_bytes() const {
  return openvdb::util::NodeMask<3>::memUsage() + 1 +
         std::size_t(kLeafSide * kLeafSide * kLeafSide) * sizeof(float) * std::size_t(channels_);
}

std::int64_t DenseVdbLayout::leaf_order(std::array<int, 3> block) const {
  const std::array<std::int64_t, 3> n{dims_.nx, dims_.ny, dims_.nz};
  // Leaves along `axis` in voxels [a, b) of the volume, a on a leaf boundary.
  const auto leaves_in = [&](int axis, std::int64_t a, std::int64_t b) {
    b = std::min(b, n[std::size_t(axis)]);
    return b <= a ? std::int64_t(0) : ceil_div(b, kLeafSide) - a / kLeafSide;
  };
  // At each level the children that meet the volume form a box, and the leaves of a child are
  // the product of its leaves along each axis, so the leaves in the children before this one
  // (x slowest, z fastest) come from per-axis counts.
  std::array<std::int64_t, 3> parent{0, 0, 0};
  std::int64_t parent_dim = std::numeric_limits<std::int64_t>::max() / 2;
  std::int64_t order = 0;
  for (const std::int64_t dim : std::array{kUpperDim, kLowerDim, kLeafSide}) {
    std::array<std::int64_t, 3> child{}, before{}, inside{}, total{};
    for (int a = 0; a < 3; ++a) {
      const auto i = std::size_t(a);
      child[i] = std::int64_t(block[i]) * kLeafSide / dim * dim;
      before[i] = leaves_in(a, parent[i], child[i]);
      inside[i] = leaves_in(a, child[i], child[i] + dim);
      total[i] = leaves_in(a, parent[i], parent[i] + parent_dim);
    }
    order += before[0] * total[1] * total[2] + inside[0] * before[1] * total[2] +
             inside[0] * inside[1] * before[2];
    parent = child;
    parent_dim = dim;
  }
  return order;
}

VdbHead DenseVdbLayout::head(const std::string& grid_name, std::string_view uuid,
                             std::span<const std::int64_t> value_bytes,
                             std::uint64_t records_bytes) const {
  TEXSIM_VERIFY(uuid.size() == 36, "a .vdb UUID has 36 characters, got '" << uuid << "'");
  const bool compressed = compression_ != VdbCompression::none;
  TEXSIM_VERIFY(!compressed || std::int64_t(value_bytes.size()) == leaf_count(),
                "a compressed .vdb head lists " << leaf_count() << " leaf sizes, got "
                                                << value_bytes.size());
  initialize_openvdb();
  std::ostringstream os(std::ios::binary);
  // The file header, as openvdb::io::Archive::writeHeader writes it.
  write_pod(os, std::int64_t(openvdb::OPENVDB_MAGIC));
  write_pod(os, std::uint32_t(openvdb::OPENVDB_FILE_VERSION));
  write_pod(os, std::uint32_t(openvdb::OPENVDB_LIBRARY_MAJOR_VERSION));
  write_pod(os, std::uint32_t(openvdb::OPENVDB_LIBRARY_MINOR_VERSION));
  write_pod(os, char(1)); // the file has grid offsets
  TEXSIM_ASSERT(std::size_t(os.tellp()) == kUuidAt, "the UUID starts at byte " << os.tellp());
  os.write(uuid.data(), static_cast<std::streamsize>(uuid.size()));
  openvdb::MetaMap().writeMeta(os); // no file metadata
  write_pod(os, std::int32_t(1));   // one grid
  return with_grid_type(channels_, [&](auto grid) {
    using Grid = decltype(grid);
    openvdb::io::GridDescriptor descriptor(grid_name, Grid::gridType());
    descriptor.writeHeader(os);
    const auto positions_at = static_cast<std::size_t>(os.tellp());
    // The grid's stream positions depend on the head's own length: written as zeros here and
    // overwritten once it is known, as openvdb::io::Archive::writeGrid seeks back to do.
    descriptor.writeStreamPos(os);
    const auto grid_at = static_cast<std::int64_t>(os.tellp());
    write_pod(os, openvdb_flags());
    describe_dense_grid(grid, dims_, {1.0, 1.0, 1.0}, {0.0, 0.0, 0.0}, grid_name);
    // Every leaf's inactive voxels hold the background, so none needs a selection mask when
    // loaded lazily; a compressed leaf's stored size lets a reader skip it.
    openvdb::io::DelayedLoadMetadata lazy;
    lazy.resizeMask(static_cast<std::size_t>(leaf_count()));
    if (compressed)
      lazy.resizeCompressedSize(static_cast<std::size_t>(leaf_count()));
    for (std::size_t i = 0; i < std::size_t(leaf_count()); ++i) {
      lazy.setMask(i, openvdb::io::NO_MASK_OR_INACTIVE_VALS);
      if (compressed)
        lazy.setCompressedSize(i, value_bytes[i]);
    }
    grid.insertMeta(openvdb::GridBase::META_FILE_DELAYED_LOAD, lazy);
    add_statistics(grid, dims_, tree_memory_bytes(), openvdb_flags());
    grid.writeMeta(os);
    grid.writeTransform(os);

    std::string bytes = os.str();
    const auto block_at = static_cast<std::int64_t>(bytes.size() + topology_bytes());
    descriptor.setGridPos(grid_at);
    descriptor.setBlockPos(block_at);
    descriptor.setEndPos(block_at + static_cast<std::int64_t>(records_bytes));
    std::ostringstream positions(std::ios::binary);
    descriptor.writeStreamPos(positions);
    bytes.replace(positions_at, positions.str().size(), positions.str());
    return VdbHead{std::move(bytes), std::uint64_t(block_at)};
  });
}

std::int64_t DenseVdbLayout::tree_memory_bytes() const {
  const auto nodes = [&](std::int64_t dim) {
    return ceil_div(dims_.nx, dim) * ceil_div(dims_.ny, dim) * ceil_div(dims_.nz, dim);
  };
  return with_grid_type(channels_, [&](auto grid) {
    using Tree = typename decltype(grid)::TreeType;
    using TreeUpper = typename Tree::RootNodeType::ChildNodeType;
    using TreeLower = typename TreeUpper::ChildNodeType;
    // What openvdb::tools::memUsage counts: the tree and root objects, each internal node's
    // value table, masks and origin, and each leaf whole.
    const auto internal = [](auto node_tag) {
      using Node = typename decltype(node_tag)::type;
      return std::int64_t(Node::NUM_VALUES * sizeof(typename Node::UnionType) +
                          2 * Node::NodeMaskType::memUsage() + sizeof(openvdb::Coord));
    };
    return std::int64_t(sizeof(Tree) + sizeof(typename Tree::RootNodeType)) +
           nodes(kUpperDim) * internal(std::type_identity<TreeUpper>{}) +
           nodes(kLowerDim) * internal(std::type_identity<TreeLower>{}) +
           leaf_count() * std::int64_t(typename Tree::LeafNodeType().memUsage());
  });
}

std::uint64_t DenseVdbLayout::topology_bytes() const {
  if (compression_ != VdbCompression::none) {
    // Compressed internal-node values have no closed-form size: count them as written.
    std::uint64_t bytes = 0;
    write_topology([&](std::string_view part) { bytes += part.size(); });
    return bytes;
  }
  const std::uint64_t value = sizeof(float) * std::uint64_t(channels_);
  const auto nodes = [&](std::int64_t dim) {
    return std::uint64_t(ceil_div(dims_.nx, dim) * ceil_div(dims_.ny, dim) *
                         ceil_div(dims_.nz, dim));
  };
  // Each internal node: child mask, value mask, metadata byte, a value per child slot.
  const std::uint64_t upper = 2 * Upper::NodeMaskType::memUsage() + 1 + Upper::NUM_VALUES * value;
  const std::uint64_t lower = 2 * Lower::NodeMaskType::memUsage() + 1 + Lower::NUM_VALUES * value;
  const std::uint64_t leaf_mask = openvdb::util::NodeMask<3>::memUsage();
  return sizeof(std::int32_t) + value + 2 * sizeof(openvdb::Index) +
         nodes(kUpperDim) * (3 * sizeof(std::int32_t) + upper) + nodes(kLowerDim) * lower +
         std::uint64_t(leaf_count()) * leaf_mask;
}

void DenseVdbLayout::write_topology(const std::function<void(std::string_view)>& sink) const {
  const std::array<std::int64_t, 3> n{dims_.nx, dims_.ny, dims_.nz};
  std::ostringstream os(std::ios::binary);
  openvdb::io::setDataCompression(os, openvdb_flags());
  const auto emit = [&] {
    sink(os.view());
    os.str("");
  };
  // An internal node's values: a zero (the background) per slot, as no slot is a tile.
  const auto write_values = [&](std::size_t count, const auto& value_mask, const auto& child_mask) {
    with_grid_type(channels_, [&](auto grid) {
      using Value = typename decltype(grid)::ValueType;
      std::vector<Value> values(count, openvdb::zeroVal<Value>());
      openvdb::io::writeCompressedValues(os, values.data(), openvdb::Index(count), value_mask,
                                         child_mask, false);
      return 0;
    });
  };
  // Tree: one buffer; root: background 0, no tiles, one child per upper node.
  write_pod(os, std::int32_t(1));
  with_grid_type(channels_, [&](auto grid) {
    write_pod(os, openvdb::zeroVal<typename decltype(grid)::ValueType>());
    return 0;
  });
  const auto count = [&](int axis, std::int64_t dim) {
    return ceil_div(n[std::size_t(axis)], dim);
  };
  write_pod(os, openvdb::Index(0));
  write_pod(os, openvdb::Index(count(0, kUpperDim) * count(1, kUpperDim) * count(2, kUpperDim)));
  // The children of the node at `origin` of `dim` voxels a side whose children are `child_dim`.
  const auto children = [&](const std::array<std::int64_t, 3>& origin, std::int64_t dim,
                            std::int64_t child_dim, const auto& visit) {
    const std::int64_t per_side = dim / child_dim;
    for (std::int64_t i = 0; i < per_side && origin[0] + i * child_dim < n[0]; ++i)
      for (std::int64_t j = 0; j < per_side && origin[1] + j * child_dim < n[1]; ++j)
        for (std::int64_t k = 0; k < per_side && origin[2] + k * child_dim < n[2]; ++k)
          visit(std::array<std::int64_t, 3>{origin[0] + i * child_dim, origin[1] + j * child_dim,
                                            origin[2] + k * child_dim},
                static_cast<openvdb::Index>((i * per_side + j) * per_side + k));
  };
  // An internal node's head: which slots hold children, no active tiles, a value per slot.
  const auto write_internal = [&](auto node, const std::array<std::int64_t, 3>& origin,
                                  std::int64_t dim, std::int64_t child_dim) {
    using Node = typename decltype(node)::type;
    typename Node::NodeMaskType with_child, active_tile;
    children(origin, dim, child_dim,
             [&](const auto&, openvdb::Index slot) { with_child.setOn(slot); });
    with_child.save(os);
    active_tile.save(os);
    write_values(Node::NUM_VALUES, active_tile, with_child);
  };
  const std::int64_t far = std::numeric_limits<std::int32_t>::max() / kUpperDim * kUpperDim;
  children({0, 0, 0}, far, kUpperDim, [&](const auto& upper, openvdb::Index) {
    for (const std::int64_t c : upper)
      write_pod(os, std::int32_t(c));
    write_internal(std::type_identity<Upper>{}, upper, kUpperDim, kLowerDim);
    children(upper, kUpperDim, kLowerDim, [&](const auto& lower, openvdb::Index) {
      write_internal(std::type_identity<Lower>{}, lower, kLowerDim, kLeafSide);
      children(lower, kLowerDim, kLeafSide, [&](const auto& leaf, openvdb::Index) {
        openvdb::util::NodeMask<3> active;
        children(leaf, kLeafSide, 1,
                 [&](const auto&, openvdb::Index voxel) { active.setOn(voxel); });
        active.save(os);
      });
      emit();
    });
  });
  emit();
}

std::int64_t DenseVdbLayout::append_leaf_record(std::string& record, std::array<int, 3> block,
                                                std::span<const float> layer) const {
  const int x0 = block[0] * kLeafSide, y0 = block[1] * kLeafSide, z0 = block[2] * kLeafSide;
  const int dx = std::min<int>(kLeafSide, dims_.nx - x0),
            dy = std::min<int>(kLeafSide, dims_.ny - y0),
            dz = std::min<int>(kLeafSide, dims_.nz - z0);
  const std::size_t plane = std::size_t(dims_.nx) * std::size_t(dims_.ny);
  TEXSIM_VERIFY(layer.size() == plane * std::size_t(dz) * std::size_t(channels_),
                "leaf layer " << block[2] << ": " << layer.size() << " values, expected "
                              << plane * std::size_t(dz) * std::size_t(channels_));
  std::ostringstream os(std::ios::binary);
  openvdb::io::setDataCompression(os, openvdb_flags());
  const std::int64_t value_bytes = with_grid_type(channels_, [&](auto grid) {
    using Leaf = typename decltype(grid)::TreeType::LeafNodeType;
    using Value = typename Leaf::ValueType;
    Leaf leaf(openvdb::Coord(x0, y0, z0), openvdb::zeroVal<Value>(), false);
    for (int x = 0; x < dx; ++x)
      for (int y = 0; y < dy; ++y)
        for (int z = 0; z < dz; ++z) {
          const float* v =
              layer.data() + (std::size_t(z) * plane + std::size_t(y0 + y) * std::size_t(dims_.nx) +
                              std::size_t(x0 + x)) *
                                 std::size_t(channels_);
          Value value;
          if constexpr (std::is_same_v<Value, float>)
            value = v[0];
          else
            value = Value(v[0], v[1], v[2]);
          leaf.setValueOn(Leaf::coordToOffset(openvdb::Coord(x, y, z)), value);
        }
    leaf.writeBuffers(os, false);
    if (compression_ == VdbCompression::none)
      return std::int64_t(0);
    // The delayed-load size as openvdb::io::Archive lists it: the compressed values and their
    // 8-byte count.
    const openvdb::io::MaskCompress<Value, typename Leaf::NodeMaskType> mask(
        leaf.valueMask(), typename Leaf::NodeMaskType(), leaf.buffer().data(),
        openvdb::zeroVal<Value>());
    return std::int64_t(openvdb::io::writeCompressedValuesSize(leaf.buffer().data(), Leaf::SIZE,
                                                               leaf.valueMask(), mask.metadata,
                                                               false, openvdb_flags())) +
           std::int64_t(sizeof(std::int64_t));
  });
  record += os.view();
  return value_bytes;
}

} // namespace texsim::vol
