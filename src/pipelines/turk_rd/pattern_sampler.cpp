#include "pipelines/turk_rd/pattern_sampler.hpp"

#include "core/error.hpp"

#include <nanoflann.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>

namespace texsim::pipelines::turk_rd {
namespace {

/// nanoflann's view of the cell positions.
struct CellCloud {
  std::span<const geom::Vec3> points;
  std::size_t kdtree_get_point_count() const { return points.size(); }
  double kdtree_get_pt(std::uint32_t i, std::size_t dim) const { return points[i][dim]; }
  template <class Box> bool kdtree_get_bbox(Box&) const { return false; }
};

using CellTree =
    nanoflann::KDTreeSingleIndexAdaptor<nanoflann::L2_Simple_Adaptor<double, CellCloud>, CellCloud,
                                        3, std::uint32_t>;

struct Entry {
  std::int64_t id;
  std::uint32_t cell;
  double weight;
};

/// The cell nearest to `p`; among cells at exactly the same distance the one with the smallest id,
/// so the choice does not depend on the order of the cells.
std::uint32_t nearest_cell(const CellTree& tree, std::span<const std::int64_t> ids, const double* p,
                           std::vector<std::pair<std::uint32_t, double>>& scratch) {
  std::uint32_t best = 0;
  double best_d2 = 0.0;
  tree.knnSearch(p, 1, &best, &best_d2);
  // Every cell tied with the one found lies strictly inside a slightly larger ball.
  const double ball = std::max(best_d2 * (1.0 + 1e-12), std::numeric_limits<double>::min());
  scratch.clear();
  tree.radiusSearch(p, ball, scratch, nanoflann::SearchParams(32, 0.0f, false));
  for (const auto& [cell, d2] : scratch) {
    if (d2 < best_d2 || (d2 == best_d2 && ids[cell] < ids[best])) {
      best = cell;
      best_d2 = d2;
    }
  }
  return best;
}

} // namespace

double turk_falloff(double d) {
  return d < 1.0 ? 2.0 * d * d * d - 3.0 * d * d + 1.0 : 0.0;
}

PatternSampler::PatternSampler(std::span<const geom::Vec3> targets,
                               std::span<const geom::Vec3> cells,
                               std::span<const std::int64_t> cell_ids, double radius)
    : cell_count_(cells.size()) {
  TEXSIM_VERIFY(std::isfinite(radius) && radius > 0.0,
                "PatternSampler: radius must be positive and finite, got " << radius);
  TEXSIM_VERIFY(cells.size() == cell_ids.size(),
                "PatternSampler: " << cells.size() << " cells but " << cell_ids.size() << " ids");
  TEXSIM_VERIFY(cells.size() < std::numeric_limits<std::uint32_t>::max(),
                "PatternSampler: too many cells (" << cells.size() << ")");
  TEXSIM_VERIFY(targets.empty() || !cells.empty(),
                "PatternSampler: " << targets.size() << " targets but no cells");
  {
    std::vector<std::int64_t> sorted(cell_ids.begin(), cell_ids.end());
    std::sort(sorted.begin(), sorted.end());
    const auto repeated = std::adjacent_find(sorted.begin(), sorted.end());
    TEXSIM_VERIFY(repeated == sorted.end(),
                  "PatternSampler: cell id " << *repeated << " appears twice");
  }
  const auto n_targets = static_cast<std::int64_t>(targets.size());
  row_start_.assign(targets.size() + 1, 0);
  if (targets.empty())
    return;

  const CellCloud cloud{cells};
  const CellTree tree(3, cloud, nanoflann::KDTreeSingleIndexAdaptorParams(16)); // builds the index

  // Rows are found independently per target, then packed; the packing is in target order, so the
  // stored rows do not depend on the thread count.
  std::vector<std::vector<Entry>> rows(targets.size());
  std::size_t fallbacks = 0;
#pragma omp parallel reduction(+ : fallbacks)
  {
    std::vector<std::pair<std::uint32_t, double>> found;
#pragma omp for schedule(dynamic, 256)
    for (std::int64_t t = 0; t < n_targets; ++t) {
      const double* p = targets[t].data();
      found.clear();
      // nanoflann keeps points with squared distance strictly below the bound: exactly d < 1.
      tree.radiusSearch(p, radius * radius, found, nanoflann::SearchParams(32, 0.0f, false));
      std::vector<Entry>& row = rows[t];
      row.reserve(found.size());
      for (const auto& [cell, d2] : found) {
        const double weight = turk_falloff(std::sqrt(d2) / radius);
        if (weight > 0.0)
          row.push_back({cell_ids[cell], cell, weight});
      }
      if (row.empty()) {
        const std::uint32_t cell = nearest_cell(tree, cell_ids, p, found);
        row.push_back({cell_ids[cell], cell, 1.0});
        ++fallbacks;
      }
      // Summing in id order makes the result independent of the order of the cells.
      std::sort(row.begin(), row.end(), [](const Entry& a, const Entry& b) { return a.id < b.id; });
      double total = 0.0;
      for (const Entry& e : row)
        total += e.weight;
      for (Entry& e : row)
        e.weight /= total;
    }
  }
  nearest_cell_targets_ = fallbacks;

  for (std::size_t t = 0; t < rows.size(); ++t)
    row_start_[t + 1] = row_start_[t] + rows[t].size();
  columns_.resize(row_start_.back());
  weights_.resize(row_start_.back());
#pragma omp parallel for schedule(static)
  for (std::int64_t t = 0; t < n_targets; ++t) {
    std::size_t k = row_start_[t];
    for (const Entry& e : rows[t]) {
      columns_[k] = e.cell;
      weights_[k] = e.weight;
      ++k;
    }
    std::vector<Entry>().swap(rows[t]);
  }
}

void PatternSampler::sample(std::span<const double> cell_values, std::span<double> out) const {
  TEXSIM_VERIFY(cell_values.size() == cell_count_,
                "PatternSampler::sample: " << cell_values.size() << " values for " << cell_count_
                                           << " cells");
  TEXSIM_VERIFY(out.size() == targets(), "PatternSampler::sample: output has "
                                             << out.size() << " entries for " << targets()
                                             << " targets");
  const auto n_targets = static_cast<std::int64_t>(targets());
#pragma omp parallel for schedule(static)
  for (std::int64_t t = 0; t < n_targets; ++t) {
    double sum = 0.0;
    for (std::size_t k = row_start_[t]; k < row_start_[t + 1]; ++k)
      sum += weights_[k] * cell_values[columns_[k]];
    out[t] = sum;
  }
}

std::vector<double> PatternSampler::sample(std::span<const double> cell_values) const {
  std::vector<double> out(targets());
  sample(cell_values, out);
  return out;
}

double PatternSampler::mean_cells_per_target() const {
  return targets() == 0 ? 0.0 : double(weights_.size()) / double(targets());
}

std::span<const std::uint32_t> PatternSampler::row_cells(std::size_t target) const {
  TEXSIM_VERIFY(target < targets(), "PatternSampler: target " << target << " out of range");
  return std::span<const std::uint32_t>(columns_).subspan(
      row_start_[target], row_start_[target + 1] - row_start_[target]);
}

std::span<const double> PatternSampler::row_weights(std::size_t target) const {
  TEXSIM_VERIFY(target < targets(), "PatternSampler: target " << target << " out of range");
  return std::span<const double>(weights_).subspan(row_start_[target],
                                                   row_start_[target + 1] - row_start_[target]);
}

} // namespace texsim::pipelines::turk_rd
