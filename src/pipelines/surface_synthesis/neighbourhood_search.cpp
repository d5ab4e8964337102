#include "pipelines/surface_synthesis/neighbourhood_search.hpp"

#include "core/error.hpp"
#include "pipelines/surface_synthesis/exhaustive_search.hpp"
#include "pipelines/surface_synthesis/pruned_search.hpp"
#include "pipelines/surface_synthesis/tsvq_tree.hpp"

#include <cmath>

namespace texsim::pipelines::surface_synthesis {

NeighbourhoodSearch::NeighbourhoodSearch(NeighbourhoodTable table) : table_(std::move(table)) {
  TEXSIM_VERIFY(table_.dimension > 0 && !table_.values.empty() &&
                    table_.values.size() % static_cast<std::size_t>(table_.dimension) == 0,
                "neighbourhood search: a table of " << table_.values.size()
                                                    << " values is not rows x dimension "
                                                    << table_.dimension << " with rows >= 1");
  for (std::size_t i = 0; i < table_.values.size(); ++i)
    TEXSIM_VERIFY(std::isfinite(table_.values[i]), "neighbourhood search: value "
                                                       << i % table_.dimension << " of row "
                                                       << i / table_.dimension << " is not finite");
}

NeighbourhoodSearch::~NeighbourhoodSearch() = default;

void NeighbourhoodSearch::nearest_batch(std::span<const double> queries,
                                        std::span<std::int64_t> rows) const {
  const auto d = static_cast<std::size_t>(dimension());
  TEXSIM_VERIFY(queries.size() == rows.size() * d,
                "neighbourhood search: " << queries.size() << " query values for " << rows.size()
                                         << " queries of " << d);
  for (std::size_t i = 0; i < rows.size(); ++i)
    rows[i] = nearest(queries.subspan(i * d, d));
}

double NeighbourhoodSearch::distance2(std::int64_t row, std::span<const double> query) const {
  TEXSIM_ASSERT(row >= 0 && row < rows() && query.size() == static_cast<std::size_t>(dimension()),
                "neighbourhood search: row " << row << " or query size " << query.size());
  return exact_distance2(table_.values.data() + row * table_.dimension, 1, query.data(),
                         table_.dimension);
}

std::int64_t NeighbourhoodSearch::nearest_among(std::span<const std::int64_t> candidates,
                                                std::span<const double> query) const {
  std::int64_t best = -1;
  double best_distance = 0.0;
  for (const std::int64_t row : candidates) {
    const double d = distance2(row, query);
    if (best < 0 || d < best_distance || (d == best_distance && row < best)) {
      best = row;
      best_distance = d;
    }
  }
  return best;
}

void NeighbourhoodSearch::check_query(std::span<const double> query) const {
  TEXSIM_VERIFY(query.size() == static_cast<std::size_t>(dimension()),
                "neighbourhood search: query of " << query.size() << " values, the table has "
                                                  << dimension());
  for (std::size_t c = 0; c < query.size(); ++c)
    TEXSIM_VERIFY(std::isfinite(query[c]),
                  "neighbourhood search: query value " << c << " is not finite");
}

std::unique_ptr<NeighbourhoodSearch> make_neighbourhood_search(SearchMethod method,
                                                               NeighbourhoodTable table,
                                                               const SearchOptions& options) {
  switch (method) {
  case SearchMethod::exhaustive:
    return std::make_unique<ExhaustiveSearch>(std::move(table));
  case SearchMethod::tsvq:
    return std::make_unique<TsvqSearch>(std::move(table), options.tsvq_leaf_size,
                                        options.tsvq_iterations);
  case SearchMethod::pruned:
    return std::make_unique<PrunedSearch>(std::move(table), options.pruned_components);
  }
  TEXSIM_VERIFY(false, "neighbourhood search: unknown method");
  return nullptr;
}

} // namespace texsim::pipelines::surface_synthesis
