#include "vol/parallel_vdb_writer.hpp"

#include "core/error.hpp"
#include "core/hash.hpp"
#include "par/collective.hpp"
#include "par/parallel_file.hpp"
#include "par/positional_checksum.hpp"
#include "vol/vdb_dense_layout.hpp"

#include <mpi.h>

#include <algorithm>
#include <climits>
#include <cstddef>
#include <cstdint>
#include <numeric>

namespace texsim::vol {
namespace {

constexpr int kLeafDim = DenseVdbLayout::kLeafDim;
/// Leaf layers (8 planes each) turned into records and written per collective call.
constexpr int kLayersPerCall = 4;

int round_up_to_leaf(int z) {
  return (z + kLeafDim - 1) / kLeafDim * kLeafDim;
}

/// A version-8 (RFC 9562, content-derived) UUID string from 128 bits of the file's checksum.
std::string content_uuid(std::uint64_t checksum, std::uint64_t salt) {
  std::string hex =
      hex64(checksum) + hex64(par::checksum_block(&checksum, 1, sizeof checksum, salt));
  hex[12] = '8';
  hex[16] = "89ab"[std::stoi(hex.substr(16, 1), nullptr, 16) & 3];
  return hex.substr(0, 8) + "-" + hex.substr(8, 4) + "-" + hex.substr(12, 4) + "-" +
         hex.substr(16, 4) + "-" + hex.substr(20, 12);
}

/// Where every rank's planes start and how many it has; checks that they tile [0, nz) in rank
/// order.
struct PlaneTiling {
  std::vector<int> first, count;

  PlaneTiling(const par::Comm& comm, const std::filesystem::path& path, int z_first, int planes,
              int nz)
      : first(std::size_t(comm.size)), count(std::size_t(comm.size)) {
    MPI_Allgather(&z_first, 1, MPI_INT, first.data(), 1, MPI_INT, comm.raw);
    MPI_Allgather(&planes, 1, MPI_INT, count.data(), 1, MPI_INT, comm.raw);
    par::run_collectively(comm, [&] {
      int next = 0;
      for (std::size_t r = 0; r < first.size(); ++r) {
        if (count[r] == 0)
          continue;
        TEXSIM_VERIFY(first[r] == next, path.string()
                                            << ": rank " << r << " holds planes from " << first[r]
                                            << " where plane " << next << " was expected");
        next += count[r];
      }
      TEXSIM_VERIFY(next == nz, path.string()
                                    << ": the ranks hold " << next << " planes of " << nz);
    });
  }

  int owner(int z) const {
    std::size_t r = 0;
    while (r < first.size() && !(z >= first[r] && z < first[r] + count[r]))
      ++r;
    TEXSIM_VERIFY(r < first.size(), "plane " << z << " has no rank");
    return static_cast<int>(r);
  }
};

} // namespace

void write_parallel_vdb(const par::Comm& comm, const std::filesystem::path& path, Dims dims,
                        int channels, int z_first, std::vector<float> planes,
                        const std::string& grid_name, VdbCompression compression) {
  const DenseVdbLayout layout(dims, channels, compression);
  const std::size_t plane_values =
      std::size_t(dims.nx) * std::size_t(dims.ny) * std::size_t(channels);
  TEXSIM_VERIFY(plane_values <= std::size_t(INT_MAX) && planes.size() % plane_values == 0,
                path.string() << ": " << planes.size() << " values are not whole planes of "
                              << plane_values);
  const int held = static_cast<int>(planes.size() / plane_values);
  const PlaneTiling tiling(comm, path, held > 0 ? z_first : 0, held, dims.nz);

  // The planes before this rank's first leaf boundary finish a leaf layer a lower rank starts;
  // the planes after its last one come from the ranks above.
  std::vector<int> send(std::size_t(comm.size), 0), receive(std::size_t(comm.size), 0);
  std::vector<int> send_at(std::size_t(comm.size), 0), receive_at(std::size_t(comm.size), 0);
  const int leading = held == 0 ? 0 : std::min(held, round_up_to_leaf(z_first) - z_first);
  if (leading > 0)
    send[std::size_t(tiling.owner(z_first / kLeafDim * kLeafDim))] = leading;
  const int owned_first = z_first + leading, held_end = z_first + held;
  int tail = 0;
  if (held > leading) { // this rank starts at least one layer
    const int last_layer_end = std::min(dims.nz, (held_end - 1) / kLeafDim * kLeafDim + kLeafDim);
    for (int z = held_end; z < last_layer_end; ++z) {
      const auto from = std::size_t(tiling.owner(z));
      if (receive[from] == 0)
        receive_at[from] = tail;
      ++receive[from];
      ++tail;
    }
  }
  MPI_Datatype plane_type = MPI_DATATYPE_NULL;
  MPI_Type_contiguous(static_cast<int>(plane_values), MPI_FLOAT, &plane_type);
  MPI_Type_commit(&plane_type);
  std::vector<float> tail_planes(std::size_t(tail) * plane_values);
  MPI_Alltoallv(planes.data(), send.data(), send_at.data(), plane_type, tail_planes.data(),
                receive.data(), receive_at.data(), plane_type, comm.raw);
  MPI_Type_free(&plane_type);
  planes.erase(planes.begin(),
               planes.begin() + std::ptrdiff_t(std::size_t(leading) * plane_values));
  planes.insert(planes.end(), tail_planes.begin(), tail_planes.end());
  tail_planes = {};
  const int owned_planes = static_cast<int>(planes.size() / plane_values);
  const int first_layer = owned_first / kLeafDim;
  const int layers = owned_planes == 0 ? 0 : (owned_planes + kLeafDim - 1) / kLeafDim;

  const auto [bx_count, by_count, bz_count] = layout.leaf_blocks();
  // This rank's leaves of `call` (kLayersPerCall leaf layers) in file order, so neighbours in the
  // file merge into one run.
  struct Leaf {
    std::int64_t order;
    std::array<int, 3> block;
  };
  const auto leaves_of_call = [&](int call) {
    std::vector<Leaf> leaves;
    for (int layer = call * kLayersPerCall; layer < std::min(layers, (call + 1) * kLayersPerCall);
         ++layer)
      for (int bx = 0; bx < bx_count; ++bx)
        for (int by = 0; by < by_count; ++by) {
          const std::array<int, 3> block{bx, by, first_layer + layer};
          leaves.push_back({layout.leaf_order(block), block});
        }
    std::sort(leaves.begin(), leaves.end(),
              [](const Leaf& a, const Leaf& b) { return a.order < b.order; });
    return leaves;
  };
  // The leaves' records one after the other (OpenVDB compresses each on its own), with each
  // record's size and its stored-value bytes.
  struct Records {
    std::string bytes;
    std::vector<std::size_t> sizes;
    std::vector<std::int64_t> value_bytes;
  };
  const auto make_records = [&](const std::vector<Leaf>& leaves) {
    std::vector<std::string> each(leaves.size());
    Records records{"", std::vector<std::size_t>(leaves.size()),
                    std::vector<std::int64_t>(leaves.size())};
#pragma omp parallel for schedule(dynamic, 16)
    for (std::size_t i = 0; i < leaves.size(); ++i) {
      const int z0 = leaves[i].block[2] * kLeafDim;
      const int depth = std::min(kLeafDim, dims.nz - z0);
      const std::span<const float> layer(planes.data() +
                                             std::size_t(z0 - owned_first) * plane_values,
                                         std::size_t(depth) * plane_values);
      records.value_bytes[i] = layout.append_leaf_record(each[i], leaves[i].block, layer);
      records.sizes[i] = each[i].size();
    }
    for (std::string& record : each) {
      records.bytes += record;
      record = {};
    }
    return records;
  };
  int calls = (layers + kLayersPerCall - 1) / kLayersPerCall;
  MPI_Allreduce(MPI_IN_PLACE, &calls, 1, MPI_INT, MPI_MAX, comm.raw);

  // Where each of this rank's leaves starts in the file, in the order the calls visit them, and
  // rank 0's head (its UUID, a fixed 36 characters, is put in once the leaves are written).
  std::vector<std::uint64_t> leaf_at;
  VdbHead head;
  if (layout.compression() == VdbCompression::none) {
    const std::uint64_t record_bytes = layout.uncompressed_leaf_record_bytes();
    if (comm.is_root())
      head = layout.head(grid_name, std::string(36, '0'), {},
                         std::uint64_t(layout.leaf_count()) * record_bytes);
    MPI_Bcast(&head.leaves_at, 1, MPI_UINT64_T, 0, comm.raw);
    for (int call = 0; call < calls; ++call)
      for (const Leaf& leaf : leaves_of_call(call))
        leaf_at.push_back(head.leaves_at + std::uint64_t(leaf.order) * record_bytes);
  } else {
    // Compressed records differ in size: every rank measures its own (compressing them once
    // here and again when writing, so no rank holds more than a call's records), rank 0 lays
    // them out in file order and lists them in the head, and returns each rank its offsets. While
    // it does, rank 0 holds six 8-byte integers a leaf (a 1024^3 volume has 2 M leaves: 96 MB),
    // as the delayed-load table it writes needs every leaf's size.
    std::vector<std::int64_t> measured; // (order, record bytes, value bytes) per leaf
    for (int call = 0; call < calls; ++call) {
      const std::vector<Leaf> leaves = leaves_of_call(call);
      const Records records = make_records(leaves);
      for (std::size_t i = 0; i < leaves.size(); ++i)
        measured.insert(measured.end(),
                        {leaves[i].order, std::int64_t(records.sizes[i]), records.value_bytes[i]});
    }
    const int sent = static_cast<int>(measured.size());
    std::vector<int> counts(std::size_t(comm.size)), displacements(std::size_t(comm.size));
    MPI_Gather(&sent, 1, MPI_INT, counts.data(), 1, MPI_INT, 0, comm.raw);
    std::vector<std::int64_t> all;
    if (comm.is_root()) {
      std::exclusive_scan(counts.begin(), counts.end(), displacements.begin(), 0);
      all.resize(std::size_t(displacements.back() + counts.back()));
    }
    MPI_Gatherv(measured.data(), sent, MPI_INT64_T, all.data(), counts.data(), displacements.data(),
                MPI_INT64_T, 0, comm.raw);
    std::vector<std::int64_t> offsets; // per gathered leaf, in the ranks' own orders
    if (comm.is_root()) {
      const auto leaves = std::size_t(layout.leaf_count());
      std::vector<std::int64_t> record_bytes(leaves), value_bytes(leaves);
      for (std::size_t i = 0; i < all.size(); i += 3) {
        record_bytes[std::size_t(all[i])] = all[i + 1];
        value_bytes[std::size_t(all[i])] = all[i + 2];
      }
      std::vector<std::int64_t> starts(leaves);
      std::exclusive_scan(record_bytes.begin(), record_bytes.end(), starts.begin(),
                          std::int64_t(0));
      head = layout.head(grid_name, std::string(36, '0'), value_bytes,
                         std::uint64_t(starts.back() + record_bytes.back()));
      for (std::size_t i = 0; i < all.size(); i += 3)
        offsets.push_back(std::int64_t(head.leaves_at) + starts[std::size_t(all[i])]);
      for (auto& c : counts)
        c /= 3;
      for (auto& d : displacements)
        d /= 3;
    }
    leaf_at.resize(measured.size() / 3);
    MPI_Scatterv(offsets.data(), counts.data(), displacements.data(), MPI_INT64_T, leaf_at.data(),
                 static_cast<int>(leaf_at.size()), MPI_INT64_T, 0, comm.raw);
  }

  par::ParallelFile file(comm, path);
  std::uint64_t checksum = 0;
  std::size_t next = 0; // index into leaf_at
  for (int call = 0; call < calls; ++call) {
    const std::vector<Leaf> leaves = leaves_of_call(call);
    const Records records = make_records(leaves);
    std::vector<par::ByteRun> runs;
    const std::byte* record = reinterpret_cast<const std::byte*>(records.bytes.data());
    for (std::size_t i = 0; i < leaves.size(); ++i, ++next) {
      const std::span<const std::byte> bytes(record, records.sizes[i]);
      record += records.sizes[i];
      // Every byte of the leaf records counts at its place in the file: the same checksum for
      // any split.
      checksum += par::checksum_block(bytes.data(), bytes.size(), 1, leaf_at[next]);
      if (!runs.empty() && runs.back().offset + runs.back().bytes.size() == leaf_at[next])
        runs.back().bytes = {runs.back().bytes.data(), runs.back().bytes.size() + bytes.size()};
      else
        runs.push_back({leaf_at[next], bytes});
    }
    file.write_runs(runs);
  }
  checksum = par::checksum_sum_over_ranks(comm, checksum);
  par::run_collectively(comm, [&] {
    if (!comm.is_root())
      return;
    const std::string uuid = content_uuid(checksum, dims.count());
    head.bytes.replace(DenseVdbLayout::kUuidAt, uuid.size(), uuid);
    file.write_at(0, std::as_bytes(std::span(head.bytes)));
    std::uint64_t at = head.bytes.size();
    layout.write_topology([&](std::string_view bytes) {
      file.write_at(at, std::as_bytes(std::span(bytes)));
      at += bytes.size();
    });
    TEXSIM_VERIFY(at == head.leaves_at, path.string() << ": topology of " << at - head.bytes.size()
                                                      << " bytes, expected "
                                                      << head.leaves_at - head.bytes.size());
  });
  file.commit();
}

} // namespace texsim::vol
