#include "pipelines/turk_rd/initiators.hpp"

#include "core/error.hpp"
#include "geom/point_expression.hpp"

#include <mpi.h>

#include <algorithm>
#include <limits>

namespace texsim::pipelines::turk_rd {

std::vector<char> select_initiator_cells(const par::Comm& comm, const geom::SurfaceCells& cells,
                                         const InitiatorSettings& initiator,
                                         const std::vector<std::string>& names,
                                         const std::vector<std::span<const double>>& columns) {
  const std::int32_t n = cells.owned_count();
  std::vector<char> selected(std::size_t(n), 0);
  if (initiator.at) {
    // Nearest cell over all ranks: smallest (distance, id).
    struct Candidate {
      double distance;
      std::int64_t id;
    };
    Candidate best{std::numeric_limits<double>::infinity(), -1};
    for (std::int32_t i = 0; i < n; ++i) {
      const double d = (cells.points()[i].position - *initiator.at).norm();
      if (d < best.distance || (d == best.distance && cells.ids()[i] < best.id))
        best = {d, cells.ids()[i]};
    }
    std::vector<Candidate> all(std::size_t(comm.size));
    MPI_Allgather(&best, sizeof best, MPI_BYTE, all.data(), sizeof best, MPI_BYTE, comm.raw);
    const auto nearest = std::min_element(all.begin(), all.end(), [](auto& a, auto& b) {
      return a.distance < b.distance || (a.distance == b.distance && a.id >= 0 && a.id < b.id);
    });
    for (std::int32_t i = 0; i < n; ++i)
      selected[i] = cells.ids()[i] == nearest->id ||
                    (cells.points()[i].position - *initiator.at).norm() <= initiator.radius;
  } else {
    std::vector<double> xyz;
    for (const auto& p : cells.points())
      xyz.insert(xyz.end(), p.position.data(), p.position.data() + 3);
    const auto value =
        geom::PointExpression(initiator.region, names, initiator.key_path + ".region")
            .evaluate(xyz, columns);
    for (std::int32_t i = 0; i < n; ++i)
      selected[i] = value[i] != 0.0;
  }
  std::int64_t local = std::count(selected.begin(), selected.end(), 1), total = 0;
  MPI_Allreduce(&local, &total, 1, MPI_INT64_T, MPI_SUM, comm.raw);
  if (total == 0)
    throw InputError(initiator.key_path +
                     ": selects no cell (the region is empty on this surface)");
  return selected;
}

} // namespace texsim::pipelines::turk_rd
