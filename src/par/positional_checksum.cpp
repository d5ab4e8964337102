#include "par/positional_checksum.hpp"

#include <cstring>

namespace texsim::par {
namespace {

std::uint64_t splitmix64(std::uint64_t x) {
  x += 0x9e3779b97f4a7c15ULL;
  x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ULL;
  x = (x ^ (x >> 27)) * 0x94d049bb133111ebULL;
  return x ^ (x >> 31);
}

} // namespace

std::uint64_t checksum_block(const void* values, std::size_t count, std::size_t scalar_size,
                             std::uint64_t first_index) {
  const auto* bytes = static_cast<const unsigned char*>(values);
  std::uint64_t sum = 0;
  for (std::size_t i = 0; i < count; ++i) {
    std::uint64_t bits = 0;
    std::memcpy(&bits, bytes + i * scalar_size, scalar_size);
    sum += splitmix64(splitmix64(first_index + i) ^ bits);
  }
  return sum;
}

std::uint64_t checksum_sum_over_ranks(const par::Comm& comm, std::uint64_t local) {
  std::uint64_t total = 0;
  MPI_Allreduce(&local, &total, 1, MPI_UINT64_T, MPI_SUM, comm.raw);
  return total;
}

} // namespace texsim::par
