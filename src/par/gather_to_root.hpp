#pragma once
/// Gathering arrays of any size on one rank. MPI counts are int, so MPI_Gatherv cannot move more
/// than 2^31 - 1 elements per rank (a 1024^3 volume of 3-int coordinates already needs 3.2 G);
/// here each rank's part travels as point-to-point messages of at most `max_message` bytes.
#include "par/comm.hpp"

#include <cstddef>
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

} // namespace texsim::par
