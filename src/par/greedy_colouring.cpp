#include "par/greedy_colouring.hpp"

#include "core/error.hpp"
#include "par/id_runs.hpp"
#include "par/record_exchange.hpp"

#include <mpi.h>

#include <algorithm>
#include <numeric>

namespace texsim::par {
namespace {

struct ClassUpdate {
  std::int64_t id;
  std::int64_t colour; // 64 bits: the record has no padding bytes to send
};

/// Owned vertices are slots [0, owned); the neighbours owned elsewhere (ghosts) follow in id order.
class Slots {
public:
  Slots(std::int64_t first, std::int64_t owned, const OwnedAdjacency& adjacency,
        const std::function<std::uint64_t(std::int64_t)>& priority)
      : first_(first), owned_(owned) {
    for (const std::int64_t v : adjacency.neighbours)
      if (v < first || v >= first + owned)
        ghosts_.push_back(v);
    std::sort(ghosts_.begin(), ghosts_.end());
    ghosts_.erase(std::unique(ghosts_.begin(), ghosts_.end()), ghosts_.end());
    keys_.resize(std::size_t(count()));
    for (std::int64_t s = 0; s < count(); ++s)
      keys_[std::size_t(s)] = priority(id(s));
  }

  std::int64_t count() const { return owned_ + std::int64_t(ghosts_.size()); }
  std::int64_t id(std::int64_t slot) const {
    return slot < owned_ ? first_ + slot : ghosts_[std::size_t(slot - owned_)];
  }
  std::int64_t slot(std::int64_t id) const {
    if (id >= first_ && id < first_ + owned_)
      return id - first_;
    const auto it = std::lower_bound(ghosts_.begin(), ghosts_.end(), id);
    TEXSIM_ASSERT(it != ghosts_.end() && *it == id, "greedy_colouring: an unknown ghost " << id);
    return owned_ + (it - ghosts_.begin());
  }
  /// Whether slot a comes before slot b in the priority order.
  bool earlier(std::int64_t a, std::int64_t b) const {
    const auto ka = keys_[std::size_t(a)], kb = keys_[std::size_t(b)];
    return ka != kb ? ka < kb : id(a) < id(b);
  }

private:
  std::int64_t first_, owned_;
  std::vector<std::int64_t> ghosts_;
  std::vector<std::uint64_t> keys_;
};

} // namespace

GreedyColouring greedy_colouring(const Comm& comm, std::span<const std::int64_t> rank_offsets,
                                 OwnedAdjacency adjacency,
                                 const std::function<std::uint64_t(std::int64_t)>& priority) {
  const std::int64_t first = rank_offsets[std::size_t(comm.rank)];
  const std::int64_t owned = rank_offsets[std::size_t(comm.rank) + 1] - first;
  TEXSIM_VERIFY(std::int64_t(adjacency.offsets.size()) == owned + 1,
                "greedy_colouring: " << adjacency.offsets.size() - 1 << " rows for " << owned
                                     << " owned vertices");
  const Slots slots(first, owned, adjacency, priority);

  // The rows as slots (in place); per owned vertex the earlier neighbours it waits for; per ghost
  // the owned vertices that wait for it.
  auto& row_slots = adjacency.neighbours;
  std::vector<std::int32_t> waiting(std::size_t(owned), 0);
  std::vector<std::int64_t> ghost_offsets(std::size_t(slots.count() - owned) + 1, 0);
  for (std::int64_t u = 0; u < owned; ++u)
    for (auto k = adjacency.offsets[std::size_t(u)]; k < adjacency.offsets[std::size_t(u) + 1];
         ++k) {
      const std::int64_t s = slots.slot(row_slots[std::size_t(k)]);
      row_slots[std::size_t(k)] = s;
      if (slots.earlier(s, u)) {
        ++waiting[std::size_t(u)];
        if (s >= owned)
          ++ghost_offsets[std::size_t(s - owned) + 1];
      }
    }
  std::partial_sum(ghost_offsets.begin(), ghost_offsets.end(), ghost_offsets.begin());
  std::vector<std::int64_t> ghost_waiters(std::size_t(ghost_offsets.back()));
  {
    auto fill = ghost_offsets;
    for (std::int64_t u = 0; u < owned; ++u)
      for (auto k = adjacency.offsets[std::size_t(u)]; k < adjacency.offsets[std::size_t(u) + 1];
           ++k) {
        const std::int64_t s = row_slots[std::size_t(k)];
        if (s >= owned && slots.earlier(s, u))
          ghost_waiters[std::size_t(fill[std::size_t(s - owned)]++)] = u;
      }
  }

  std::vector<std::int32_t> slot_class(std::size_t(slots.count()), -1);
  std::vector<std::int64_t> ready;
  for (std::int64_t u = 0; u < owned; ++u)
    if (waiting[std::size_t(u)] == 0)
      ready.push_back(u);
  std::vector<std::int64_t> taken_by; // taken_by[c] == u: an earlier neighbour of u has class c
  std::vector<int> destinations;
  GreedyColouring result;
  std::int64_t uncoloured = owned;
  for (;;) {
    std::vector<std::vector<ClassUpdate>> outgoing(std::size_t(comm.size));
    std::int64_t coloured_now = 0;
    while (!ready.empty()) {
      const std::int64_t u = ready.back();
      ready.pop_back();
      const auto begin = adjacency.offsets[std::size_t(u)];
      const auto end = adjacency.offsets[std::size_t(u) + 1];
      for (auto k = begin; k < end; ++k) {
        const std::int64_t s = row_slots[std::size_t(k)];
        if (!slots.earlier(s, u))
          continue;
        const auto c = std::size_t(slot_class[std::size_t(s)]);
        if (c >= taken_by.size())
          taken_by.resize(c + 1, -1);
        taken_by[c] = u;
      }
      std::int32_t colour = 0;
      while (std::size_t(colour) < taken_by.size() && taken_by[std::size_t(colour)] == u)
        ++colour;
      slot_class[std::size_t(u)] = colour;
      ++coloured_now;
      // Later neighbours wait for u: owned ones here, ghosts on their owners.
      destinations.clear();
      for (auto k = begin; k < end; ++k) {
        const std::int64_t s = row_slots[std::size_t(k)];
        if (slots.earlier(s, u))
          continue;
        if (s < owned) {
          if (--waiting[std::size_t(s)] == 0)
            ready.push_back(s);
        } else {
          destinations.push_back(owner_of(rank_offsets, slots.id(s)));
        }
      }
      std::sort(destinations.begin(), destinations.end());
      destinations.erase(std::unique(destinations.begin(), destinations.end()), destinations.end());
      for (const int r : destinations)
        outgoing[std::size_t(r)].push_back({first + u, colour});
    }
    for (const auto& update : exchange_records(comm, outgoing)) {
      const std::int64_t s = slots.slot(update.id);
      slot_class[std::size_t(s)] = std::int32_t(update.colour);
      for (auto k = ghost_offsets[std::size_t(s - owned)];
           k < ghost_offsets[std::size_t(s - owned) + 1]; ++k) {
        const std::int64_t w = ghost_waiters[std::size_t(k)];
        if (--waiting[std::size_t(w)] == 0)
          ready.push_back(w);
      }
    }
    uncoloured -= coloured_now;
    std::int64_t totals[2] = {uncoloured, coloured_now};
    MPI_Allreduce(MPI_IN_PLACE, totals, 2, MPI_INT64_T, MPI_SUM, comm.raw);
    if (totals[0] == 0)
      break;
    TEXSIM_VERIFY(totals[1] > 0, "greedy_colouring: " << totals[0]
                                                      << " vertices wait for each other (the "
                                                         "graph is not symmetric across ranks)");
  }
  result.owned_class.assign(slot_class.begin(), slot_class.begin() + owned);
  const auto highest = std::max_element(result.owned_class.begin(), result.owned_class.end());
  result.classes = highest == result.owned_class.end() ? 0 : *highest + 1;
  MPI_Allreduce(MPI_IN_PLACE, &result.classes, 1, MPI_INT32_T, MPI_MAX, comm.raw);
  return result;
}

} // namespace texsim::par
