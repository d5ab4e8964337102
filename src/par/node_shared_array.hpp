#pragma once
/// Read-only arrays held once per node instead of once per rank. The memory is an MPI-3
/// shared-memory window (MPI_Win_allocate_shared) on the node's communicator
/// (MPI_Comm_split_type, MPI_COMM_TYPE_SHARED): node rank 0 owns it, every rank of the node maps
/// it. Used for data that every rank reads at random and nobody changes once built, such as
/// solid_synthesis' exemplar levels: at 64 ranks on 4 nodes it is held 4 times, not 64.
#include "core/error.hpp"
#include "par/comm.hpp"

#include <algorithm>
#include <cstddef>
#include <cstring>
#include <memory>
#include <span>
#include <type_traits>
#include <vector>

namespace texsim::par {

/// How a communicator's ranks group into nodes.
struct NodeLayout {
  /// `comm`'s ranks that share memory; `emulated_ranks_per_node` > 0 splits them further into
  /// groups of that many consecutive ranks, as if they were on separate nodes (tests and
  /// benchmarks of the multi-node path on one machine). 0 takes it from the environment variable
  /// TEXSIM_RANKS_PER_NODE when set (InputError unless a positive count), so whole runs can be
  /// checked the same way. Collective.
  static std::shared_ptr<const NodeLayout> make(const Comm& comm, int emulated_ranks_per_node = 0);
  ~NodeLayout();
  NodeLayout(const NodeLayout&) = delete;
  NodeLayout& operator=(const NodeLayout&) = delete;

  Comm world;   ///< the communicator the layout splits (not owned)
  Comm node;    ///< the ranks of this rank's node
  Comm leaders; ///< node rank 0 of every node (MPI_COMM_NULL on the other ranks)
  int node_count = 1;
  std::vector<int> node_of_rank; ///< per rank of `world`: its node's index (rank in `leaders`)
  std::vector<int> rank_in_node; ///< per rank of `world`: its rank in its node's `node`

private:
  NodeLayout() = default;
};

/// Bytes per chunk when a rank's part is spread over its node's ranks for writing.
inline constexpr std::size_t kNodeChunk = std::size_t{256} << 10;

/// `count` bytes shared by the ranks of a node; the window is freed (collectively over the node)
/// when the last copy of the handle goes.
class NodeSharedBytes {
public:
  NodeSharedBytes() = default;
  /// Allocates `count` bytes on each node, aligned to 64 bytes, content unspecified. Collective
  /// over layout->world.
  NodeSharedBytes(std::shared_ptr<const NodeLayout> layout, std::size_t count);

  std::span<std::byte> bytes() const { return {data_, count_}; }
  const NodeLayout& layout() const { return *layout_; }
  /// Makes every rank's writes to the window visible to the node's other ranks (memory sync and
  /// a node barrier). Collective over the node.
  void synchronise() const;

private:
  struct Window;
  std::shared_ptr<const NodeLayout> layout_;
  std::shared_ptr<Window> window_;
  std::byte* data_ = nullptr;
  std::size_t count_ = 0;
};

/// The concatenation, in rank order, of every rank's `mine`, written once per node: each rank's
/// part goes into its node's window in chunks of `node_chunk` bytes that the node's ranks write in
/// turn (so that no rank touches, and counts in its resident memory, more than its share of the
/// pages), then every node leader receives the parts of the other nodes' ranks (broadcast over the
/// leaders in messages of at most `max_message` bytes, so no MPI count overflows). Collective over
/// layout->world.
NodeSharedBytes node_shared_concatenation(std::shared_ptr<const NodeLayout> layout,
                                          std::span<const std::byte> mine,
                                          std::size_t max_message = std::size_t{1} << 30,
                                          std::size_t node_chunk = kNodeChunk);

/// A read-only array of trivially copyable T held once per node.
template <class T> class NodeSharedArray {
  static_assert(std::is_trivially_copyable_v<T>);

public:
  NodeSharedArray() = default;
  explicit NodeSharedArray(NodeSharedBytes bytes) : bytes_(std::move(bytes)) {}

  /// Every rank's `mine` concatenated in rank order (node_shared_concatenation). Collective.
  static NodeSharedArray concatenate(std::shared_ptr<const NodeLayout> layout,
                                     std::span<const T> mine) {
    return NodeSharedArray(node_shared_concatenation(std::move(layout), std::as_bytes(mine)));
  }
  /// `root`'s `values` on every node (the other ranks' `values` are ignored). Collective.
  static NodeSharedArray from_root(std::shared_ptr<const NodeLayout> layout,
                                   std::span<const T> values, int root = 0) {
    const bool mine = layout->world.rank == root;
    return concatenate(std::move(layout), mine ? values : std::span<const T>());
  }
  /// `count` elements computed on each node: `fill(all, begin, end)` writes elements
  /// [begin, end) of `all`, and the node's ranks share the range evenly, in whole multiples of
  /// `granule` elements (which divides `count`: e.g. a grid's planes). Collective.
  template <class Fill>
  static NodeSharedArray filled(std::shared_ptr<const NodeLayout> layout, std::size_t count,
                                Fill fill, std::size_t granule = 1) {
    TEXSIM_VERIFY(granule >= 1 && count % granule == 0,
                  "node-shared array of " << count << " elements in granules of " << granule);
    const Comm node = layout->node;
    const std::size_t granules = count / granule;
    NodeSharedBytes bytes(std::move(layout), count * sizeof(T));
    const std::span<T> all(reinterpret_cast<T*>(bytes.bytes().data()), count);
    fill(all, granule * (granules * std::size_t(node.rank) / std::size_t(node.size)),
         granule * (granules * std::size_t(node.rank + 1) / std::size_t(node.size)));
    bytes.synchronise();
    return NodeSharedArray(std::move(bytes));
  }

  std::span<const T> values() const {
    const auto bytes = bytes_.bytes();
    return {reinterpret_cast<const T*>(bytes.data()), bytes.size() / sizeof(T)};
  }
  const T* data() const { return values().data(); }
  std::size_t size() const { return values().size(); }
  bool empty() const { return values().empty(); }
  const T& operator[](std::size_t i) const { return values()[i]; }
  const T* begin() const { return data(); }
  const T* end() const { return data() + size(); }

  /// The same elements (wherever each array is held).
  friend bool operator==(const NodeSharedArray& a, const NodeSharedArray& b) {
    return std::equal(a.begin(), a.end(), b.begin(), b.end());
  }

private:
  NodeSharedBytes bytes_;
};

} // namespace texsim::par
