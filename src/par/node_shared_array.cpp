#include "par/node_shared_array.hpp"

#include "core/error.hpp"

#include <algorithm>
#include <cstdint>
#include <cstdlib>

namespace texsim::par {

namespace {
Comm comm_of(MPI_Comm raw) {
  Comm comm{raw, 0, 1};
  if (raw != MPI_COMM_NULL) {
    MPI_Comm_rank(raw, &comm.rank);
    MPI_Comm_size(raw, &comm.size);
  }
  return comm;
}

/// MPI_Win_allocate_shared's alignment is only that of the platform's malloc; the window is
/// over-allocated by this much so that the array can start on a cache line.
constexpr std::size_t kAlignment = 64;
} // namespace

std::shared_ptr<const NodeLayout> NodeLayout::make(const Comm& comm, int emulated_ranks_per_node) {
  if (emulated_ranks_per_node == 0)
    if (const char* text = std::getenv("TEXSIM_RANKS_PER_NODE")) {
      char* end = nullptr;
      const long value = std::strtol(text, &end, 10);
      if (end == text || *end != '\0' || value < 1 || value > 1 << 20)
        TEXSIM_INPUT_ERROR("TEXSIM_RANKS_PER_NODE: expected a positive rank count, got '" << text
                                                                                          << "'");
      emulated_ranks_per_node = static_cast<int>(value);
    }
  std::shared_ptr<NodeLayout> layout(new NodeLayout);
  layout->world = comm;
  MPI_Comm shared = MPI_COMM_NULL;
  MPI_Comm_split_type(comm.raw, MPI_COMM_TYPE_SHARED, comm.rank, MPI_INFO_NULL, &shared);
  MPI_Comm node = shared;
  if (emulated_ranks_per_node > 0) {
    MPI_Comm_split(shared, comm.rank / emulated_ranks_per_node, comm.rank, &node);
    MPI_Comm_free(&shared);
  }
  layout->node = comm_of(node);
  MPI_Comm leaders = MPI_COMM_NULL;
  MPI_Comm_split(comm.raw, layout->node.rank == 0 ? 0 : MPI_UNDEFINED, comm.rank, &leaders);
  layout->leaders = comm_of(leaders);
  // Each rank learns its node's index from its leader, then every rank learns everybody's.
  int node_index = layout->leaders.rank;
  MPI_Bcast(&node_index, 1, MPI_INT, 0, node);
  layout->node_of_rank.resize(std::size_t(comm.size));
  MPI_Allgather(&node_index, 1, MPI_INT, layout->node_of_rank.data(), 1, MPI_INT, comm.raw);
  layout->node_count =
      *std::max_element(layout->node_of_rank.begin(), layout->node_of_rank.end()) + 1;
  layout->rank_in_node.resize(std::size_t(comm.size));
  MPI_Allgather(&layout->node.rank, 1, MPI_INT, layout->rank_in_node.data(), 1, MPI_INT, comm.raw);
  return layout;
}

NodeLayout::~NodeLayout() {
  if (leaders.raw != MPI_COMM_NULL)
    MPI_Comm_free(&leaders.raw);
  if (node.raw != MPI_COMM_NULL)
    MPI_Comm_free(&node.raw);
}

struct NodeSharedBytes::Window {
  MPI_Win win = MPI_WIN_NULL;
  ~Window() {
    if (win != MPI_WIN_NULL)
      MPI_Win_free(&win);
  }
};

NodeSharedBytes::NodeSharedBytes(std::shared_ptr<const NodeLayout> layout, std::size_t count)
    : layout_(std::move(layout)), window_(std::make_shared<Window>()), count_(count) {
  const bool owner = layout_->node.rank == 0;
  const auto size = static_cast<MPI_Aint>(owner ? count + kAlignment : 0);
  void* base = nullptr;
  const int status =
      MPI_Win_allocate_shared(size, 1, MPI_INFO_NULL, layout_->node.raw, &base, &window_->win);
  TEXSIM_VERIFY(status == MPI_SUCCESS, "MPI_Win_allocate_shared of " << count << " bytes failed");
  MPI_Aint owner_size = 0;
  int unit = 0;
  MPI_Win_shared_query(window_->win, 0, &owner_size, &unit, &base);
  const auto address = reinterpret_cast<std::uintptr_t>(base);
  data_ = static_cast<std::byte*>(base) + (kAlignment - address % kAlignment) % kAlignment;
}

void NodeSharedBytes::synchronise() const {
  // Shared-memory windows follow the unified model: a sync plus a barrier orders the node's
  // stores before everybody's later loads.
  MPI_Win_lock_all(MPI_MODE_NOCHECK, window_->win);
  MPI_Win_sync(window_->win);
  MPI_Barrier(layout_->node.raw);
  MPI_Win_sync(window_->win);
  MPI_Win_unlock_all(window_->win);
}

NodeSharedBytes node_shared_concatenation(std::shared_ptr<const NodeLayout> layout,
                                          std::span<const std::byte> mine, std::size_t max_message,
                                          std::size_t node_chunk) {
  const Comm& world = layout->world;
  std::vector<std::uint64_t> sizes(std::size_t(world.size));
  const std::uint64_t my_size = mine.size();
  MPI_Allgather(&my_size, 1, MPI_UINT64_T, sizes.data(), 1, MPI_UINT64_T, world.raw);
  std::vector<std::uint64_t> offsets(sizes.size() + 1, 0);
  for (std::size_t r = 0; r < sizes.size(); ++r)
    offsets[r + 1] = offsets[r] + sizes[r];

  NodeSharedBytes shared(layout, offsets.back());
  const std::span<std::byte> out = shared.bytes();
  // Chunk j of a part is written by node rank j mod (node size): the owner copies the chunks
  // that fall to it and sends the others, which their writers receive straight into the window.
  const Comm& node = layout->node;
  const int my_node = layout->node_of_rank[std::size_t(world.rank)];
  std::vector<MPI_Request> requests;
  for (std::size_t r = 0; r < sizes.size(); ++r) {
    if (layout->node_of_rank[r] != my_node)
      continue;
    const int owner = layout->rank_in_node[r];
    const bool owned = int(r) == world.rank;
    for (std::uint64_t begin = 0, chunk = 0; begin < sizes[r]; begin += node_chunk, ++chunk) {
      const auto length = static_cast<int>(std::min<std::uint64_t>(node_chunk, sizes[r] - begin));
      const int writer = static_cast<int>(chunk % std::uint64_t(node.size));
      std::byte* target = out.data() + offsets[r] + begin;
      if (owned && writer == node.rank) {
        std::memcpy(target, mine.data() + begin, std::size_t(length));
      } else if (owned) {
        requests.emplace_back();
        MPI_Isend(mine.data() + begin, length, MPI_BYTE, writer, 0, node.raw, &requests.back());
      } else if (writer == node.rank) {
        requests.emplace_back();
        MPI_Irecv(target, length, MPI_BYTE, owner, 0, node.raw, &requests.back());
      }
    }
  }
  MPI_Waitall(static_cast<int>(requests.size()), requests.data(), MPI_STATUSES_IGNORE);
  shared.synchronise();
  if (layout->node_count > 1 && layout->leaders.raw != MPI_COMM_NULL) {
    // Rank r's part, already in its own node's window, goes from that node's leader to the others.
    for (std::size_t r = 0; r < sizes.size(); ++r) {
      const int root = layout->node_of_rank[r];
      for (std::uint64_t begin = 0; begin < sizes[r]; begin += max_message) {
        const std::uint64_t length = std::min<std::uint64_t>(max_message, sizes[r] - begin);
        MPI_Bcast(out.data() + offsets[r] + begin, static_cast<int>(length), MPI_BYTE, root,
                  layout->leaders.raw);
      }
    }
  }
  shared.synchronise();
  return shared;
}

} // namespace texsim::par
