#include "par/gather_to_root.hpp"

#include "core/error.hpp"

#include <algorithm>
#include <vector>

namespace texsim::par {
namespace {

/// `bytes` to `destination` in messages of at most `max_message` bytes.
void send_chunks(const Comm& comm, int destination, std::span<const std::byte> bytes,
                 std::size_t max_message, int tag) {
  for (std::size_t at = 0; at < bytes.size(); at += max_message)
    MPI_Send(bytes.data() + at, static_cast<int>(std::min(max_message, bytes.size() - at)),
             MPI_BYTE, destination, tag, comm.raw);
}

/// What send_chunks sent, into `into` (its size known beforehand).
void receive_chunks(const Comm& comm, int source, std::span<std::byte> into,
                    std::size_t max_message, int tag) {
  for (std::size_t at = 0; at < into.size(); at += max_message)
    MPI_Recv(into.data() + at, static_cast<int>(std::min(max_message, into.size() - at)), MPI_BYTE,
             source, tag, comm.raw, MPI_STATUS_IGNORE);
}

constexpr int kGatherTag = 7301;
constexpr int kScatterTag = 7302;

} // namespace

void stream_to_root(const Comm& comm, std::span<const std::byte> mine,
                    const std::function<void(int rank, std::span<const std::byte> bytes)>& consume,
                    int root, std::size_t max_message) {
  TEXSIM_VERIFY(max_message >= 1 && max_message <= kMaxGatherMessage,
                "gather_to_root: message size " << max_message << " out of range");
  const std::uint64_t my_size = mine.size();
  std::vector<std::uint64_t> sizes(comm.rank == root ? static_cast<std::size_t>(comm.size) : 0);
  MPI_Gather(&my_size, 1, MPI_UINT64_T, sizes.data(), 1, MPI_UINT64_T, root, comm.raw);
  if (comm.rank != root) {
    send_chunks(comm, root, mine, max_message, kGatherTag);
    return;
  }
  std::vector<std::byte> part;
  for (int rank = 0; rank < comm.size; ++rank) {
    if (rank == root) {
      consume(rank, mine);
      continue;
    }
    const std::uint64_t size = sizes[static_cast<std::size_t>(rank)];
    part.resize(size);
    receive_chunks(comm, rank, part, max_message, kGatherTag);
    consume(rank, part);
  }
}

std::vector<std::byte> gather_to_root(const Comm& comm, std::span<const std::byte> mine, int root,
                                      std::size_t max_message) {
  std::vector<std::byte> all;
  stream_to_root(
      comm, mine,
      [&](int, std::span<const std::byte> bytes) {
        all.insert(all.end(), bytes.begin(), bytes.end());
      },
      root, max_message);
  return all;
}

void send_part(const Comm& comm, int destination, std::span<const std::byte> bytes,
               std::size_t max_message) {
  const std::uint64_t size = bytes.size();
  MPI_Send(&size, 1, MPI_UINT64_T, destination, kScatterTag, comm.raw);
  send_chunks(comm, destination, bytes, max_message, kScatterTag);
}

std::uint64_t receive_part_size(const Comm& comm, int source) {
  std::uint64_t size = 0;
  MPI_Recv(&size, 1, MPI_UINT64_T, source, kScatterTag, comm.raw, MPI_STATUS_IGNORE);
  return size;
}

void receive_part(const Comm& comm, int source, std::span<std::byte> into,
                  std::size_t max_message) {
  receive_chunks(comm, source, into, max_message, kScatterTag);
}

} // namespace texsim::par
