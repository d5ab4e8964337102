#pragma once
/// Gathering arrays of any size on one rank, and scattering them from it. MPI counts are int, so
/// MPI_Gatherv cannot move more than 2^31 - 1 elements per rank (a 1024^3 volume of 3-int
/// coordinates already needs 3.2 G); here each rank's part travels as point-to-point messages of at
/// most `max_message` bytes.
#include "par/comm.hpp"

#include <cstddef>
#include <cstdint>
#include <cstring>
#include <functional>
#include <span>
#include <type_traits>
#include <vector>

namespace texsim::par {

/// Default message size: 1 GiB, well under MPI's int count limit.
inline constexpr std::size_t kMaxGatherMessage = std::size_t{1} << 30;

/// Every rank's bytes handed to `consume(rank, bytes)` on `root`, in rank order, one rank's part
/// at a time, so the root never holds more than the largest part (a large result can be turned
/// into its output as it arrives). Moved in messages of at most `max_message` bytes. Collective.
void stream_to_root(const Comm& comm, std::span<const std::byte> mine,
                    const std::function<void(int rank, std::span<const std::byte> bytes)>& consume,
                    int root = 0, std::size_t max_message = kMaxGatherMessage);

/// Every rank's bytes concatenated in rank order on `root` (empty on the others), moved in
/// messages of at most `max_message` bytes. Collective.
std::vector<std::byte> gather_to_root(const Comm& comm, std::span<const std::byte> mine,
                                      int root = 0, std::size_t max_message = kMaxGatherMessage);

/// The same for trivially copyable elements.
template <class T>
std::vector<T> gather_to_root(const Comm& comm, std::span<const T> mine, int root = 0,
                              std::size_t max_message = kMaxGatherMessage) {
  static_assert(std::is_trivially_copyable_v<T>);
  const auto bytes = gather_to_root(comm, std::as_bytes(mine), root, max_message);
  std::vector<T> out(bytes.size() / sizeof(T));
  if (!bytes.empty())
    std::memcpy(out.data(), bytes.data(), bytes.size());
  return out;
}

/// Raw parts of scatter_from_root: the size, then messages of at most `max_message` bytes.
void send_part(const Comm& comm, int destination, std::span<const std::byte> bytes,
               std::size_t max_message);
std::uint64_t receive_part_size(const Comm& comm, int source);
void receive_part(const Comm& comm, int source, std::span<std::byte> into, std::size_t max_message);

/// The inverse of stream_to_root: on `root`, `produce(rank)` makes one rank's part at a time (the
/// other ranks' in rank order, its own last), and each part is sent and freed before the next is
/// made, so the root holds one part besides its own, not all of them. Returns this rank's part.
/// Collective.
template <class T, class Produce>
std::vector<T> scatter_from_root(const Comm& comm, const Produce& produce, int root = 0,
                                 std::size_t max_message = kMaxGatherMessage) {
  static_assert(std::is_trivially_copyable_v<T>);
  if (comm.rank != root) {
    std::vector<T> mine(receive_part_size(comm, root) / sizeof(T));
    receive_part(comm, root, std::as_writable_bytes(std::span(mine)), max_message);
    return mine;
  }
  for (int rank = 0; rank < comm.size; ++rank)
    if (rank != root) {
      const std::vector<T> part = produce(rank);
      send_part(comm, rank, std::as_bytes(std::span(part)), max_message);
    }
  return produce(root);
}

} // namespace texsim::par
