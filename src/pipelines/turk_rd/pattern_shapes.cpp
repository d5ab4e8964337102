#include "pipelines/turk_rd/pattern_shapes.hpp"

#include "geom/graph_regions.hpp"

#include <mpi.h>

#include <algorithm>
#include <cmath>
#include <numeric>

namespace texsim::pipelines::turk_rd {
namespace {

template <typename T> MPI_Datatype mpi_type();
template <> MPI_Datatype mpi_type<double>() {
  return MPI_DOUBLE;
}
template <> MPI_Datatype mpi_type<std::int64_t>() {
  return MPI_INT64_T;
}

/// Concatenation of every rank's `local` on rank 0 (in rank order). Collective.
template <typename T>
std::vector<T> gather_to_root(const par::Comm& comm, const std::vector<T>& local) {
  int count = int(local.size());
  std::vector<int> counts(comm.size), offsets(comm.size, 0);
  MPI_Gather(&count, 1, MPI_INT, counts.data(), 1, MPI_INT, 0, comm.raw);
  std::partial_sum(counts.begin(), counts.end() - 1, offsets.begin() + 1);
  std::vector<T> all(comm.is_root() ? std::size_t(offsets.back() + counts.back()) : 0);
  MPI_Gatherv(local.data(), count, mpi_type<T>(), all.data(), counts.data(), offsets.data(),
              mpi_type<T>(), 0, comm.raw);
  return all;
}

} // namespace

PatternShapes measure_pattern(const par::Comm& comm, const geom::SurfaceCells& cells,
                              std::span<const double> owned_values) {
  // Per owned cell: id, value, area, neighbour count; per neighbour entry: id and border length.
  const auto& stencil = cells.neighbors();
  std::vector<std::int64_t> ids(cells.ids().begin(), cells.ids().end()), degrees, neighbor_ids;
  std::vector<double> values(owned_values.begin(), owned_values.end()), borders;
  std::vector<double> areas(cells.areas().begin(), cells.areas().end());
  const auto local_id = [&](std::int32_t local) {
    return local < cells.owned_count() ? cells.ids()[local]
                                       : cells.ghost_ids()[local - cells.owned_count()];
  };
  const auto local_position = [&](std::int32_t local) {
    return local < cells.owned_count() ? cells.points()[local].position
                                       : cells.ghost_positions()[local - cells.owned_count()];
  };
  for (std::int32_t i = 0; i < cells.owned_count(); ++i) {
    degrees.push_back(stencil.offsets[i + 1] - stencil.offsets[i]);
    for (std::int64_t e = stencil.offsets[i]; e < stencil.offsets[i + 1]; ++e) {
      const std::int32_t j = stencil.indices[e];
      neighbor_ids.push_back(local_id(j));
      borders.push_back(cells.couplings()[e] * (local_position(i) - local_position(j)).norm());
    }
  }
  const auto all_ids = gather_to_root(comm, ids);
  const auto all_values = gather_to_root(comm, values);
  const auto all_areas = gather_to_root(comm, areas);
  const auto all_degrees = gather_to_root(comm, degrees);
  const auto all_neighbors = gather_to_root(comm, neighbor_ids);
  const auto all_borders = gather_to_root(comm, borders);

  double result[5] = {0, 0, 0, 0, 0};
  if (comm.is_root()) {
    const std::size_t n = all_ids.size();
    // Rows by cell id, so the count does not depend on the partition.
    std::vector<std::int64_t> row_start(n + 1, 0), gathered_start(n + 1, 0);
    std::vector<std::size_t> row_of(n);
    for (std::size_t k = 0; k < n; ++k) {
      row_of[std::size_t(all_ids[k])] = k;
      gathered_start[k + 1] = gathered_start[k] + all_degrees[k];
    }
    geom::CsrAdjacency graph;
    std::vector<double> graph_borders, value(n), area(n);
    graph.offsets.assign(1, 0);
    for (std::size_t id = 0; id < n; ++id) {
      const std::size_t k = row_of[id];
      value[id] = all_values[k];
      area[id] = all_areas[k];
      for (auto e = gathered_start[k]; e < gathered_start[k + 1]; ++e) {
        graph.indices.push_back(std::int32_t(all_neighbors[e]));
        graph_borders.push_back(all_borders[e]);
      }
      graph.offsets.push_back(std::int64_t(graph.indices.size()));
    }
    const double mean = std::accumulate(value.begin(), value.end(), 0.0) / double(n);
    std::vector<char> above(n);
    for (std::size_t i = 0; i < n; ++i)
      above[i] = value[i] > mean;
    const auto labels = geom::label_regions(graph, above);
    const int regions = n ? 1 + *std::max_element(labels.begin(), labels.end()) : 0;
    std::vector<double> region_area(regions, 0.0), perimeter(regions, 0.0);
    std::vector<int> region_cells(regions, 0);
    for (std::size_t i = 0; i < n; ++i) {
      if (labels[i] < 0)
        continue;
      region_area[labels[i]] += area[i];
      ++region_cells[labels[i]];
      for (auto e = graph.offsets[i]; e < graph.offsets[i + 1]; ++e)
        if (labels[graph.indices[e]] != labels[i])
          perimeter[labels[i]] += graph_borders[e];
    }
    std::vector<double> elongation;
    double weighted_sum = 0, weight = 0;
    for (int r = 0; r < regions; ++r)
      if (region_cells[r] >= 4) {
        elongation.push_back(perimeter[r] * perimeter[r] / (4.0 * M_PI * region_area[r]));
        weighted_sum += region_cells[r] * elongation.back();
        weight += region_cells[r];
      }
    std::sort(elongation.begin(), elongation.end());
    result[0] = regions;
    result[1] = regions ? double(std::count(above.begin(), above.end(), 1)) / regions : 0.0;
    result[2] = elongation.empty() ? 0.0 : elongation[elongation.size() / 2];
    result[3] = elongation.empty() ? 0.0 : elongation.back();
    result[4] = weight > 0 ? weighted_sum / weight : 0.0;
  }
  MPI_Bcast(result, 5, MPI_DOUBLE, 0, comm.raw);
  return {int(result[0]), result[1], result[2], result[3], result[4]};
}

} // namespace texsim::pipelines::turk_rd
