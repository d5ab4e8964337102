#include "pipelines/turk_rd/region_moments.hpp"

#include "geom/distributed_regions.hpp"
#include "par/ghosted_vector.hpp"
#include "par/labelled_sums.hpp"

#include <algorithm>

namespace texsim::pipelines::turk_rd {
namespace {

/// The cell graph on this rank's owned cells and ghosts, symmetric: the ghosts' rows hold the owned
/// cells next to them, so two owned cells joined only through a ghost share a local component.
geom::CsrAdjacency local_graph(const geom::SurfaceCells& cells) {
  const auto& stencil = cells.neighbors();
  const std::int32_t owned = cells.owned_count();
  const auto nodes = std::size_t(owned) + cells.ghost_ids().size();
  geom::CsrAdjacency graph;
  graph.offsets.assign(nodes + 1, 0);
  for (std::int32_t i = 0; i < owned; ++i) {
    graph.offsets[i + 1] += stencil.offsets[i + 1] - stencil.offsets[i];
    for (const std::int32_t j : stencil.row(i))
      if (j >= owned)
        ++graph.offsets[j + 1];
  }
  for (std::size_t v = 0; v < nodes; ++v)
    graph.offsets[v + 1] += graph.offsets[v];
  graph.indices.resize(std::size_t(graph.offsets.back()));
  std::vector<std::int64_t> next(graph.offsets.begin(), graph.offsets.end() - 1);
  for (std::int32_t i = 0; i < owned; ++i)
    for (const std::int32_t j : stencil.row(i)) {
      graph.indices[next[i]++] = j;
      if (j >= owned)
        graph.indices[next[j]++] = i;
    }
  return graph;
}

} // namespace

std::vector<std::int64_t> label_cell_regions(const par::Comm& comm, const geom::SurfaceCells& cells,
                                             std::span<const char> owned_marked) {
  const std::int32_t owned = cells.owned_count();
  par::GhostedVector halo(comm, owned, cells.ghost_blocks());
  std::vector<double> marks(owned_marked.begin(), owned_marked.end());
  halo.set_owned(marks);
  const std::span<const double> local_marks = halo.local();
  std::vector<char> marked(local_marks.size());
  std::vector<std::int64_t> ids(local_marks.size());
  for (std::size_t i = 0; i < local_marks.size(); ++i) {
    marked[i] = local_marks[i] != 0;
    ids[i] = i < std::size_t(owned) ? cells.ids()[i] : cells.ghost_ids()[i - std::size_t(owned)];
  }
  return geom::label_regions_across_ranks(
      comm, local_graph(cells), marked, ids, owned, [&](std::span<double> local) {
        halo.set_owned(local.first(std::size_t(owned)));
        std::copy(halo.local().begin() + owned, halo.local().end(), local.begin() + owned);
      });
}

Eigen::Vector3d centre_of(const RegionMoments& region) {
  return Eigen::Vector3d(region.first[0], region.first[1], region.first[2]) / region.area;
}

Eigen::Matrix3d covariance_of(const RegionMoments& region) {
  const auto& s = region.second;
  Eigen::Matrix3d second;
  second << s[0], s[1], s[2], s[1], s[3], s[4], s[2], s[4], s[5];
  const Eigen::Vector3d mean = centre_of(region);
  return second / region.area - mean * mean.transpose();
}

std::vector<RegionMoments> region_moments_on_root(const par::Comm& comm,
                                                  const geom::SurfaceCells& cells,
                                                  std::span<const std::int64_t> labels) {
  const std::int32_t owned = cells.owned_count();
  const auto position = [&](std::int32_t local) {
    return local < owned ? cells.points()[local].position : cells.ghost_positions()[local - owned];
  };
  // Per owned cell: area, then its area-weighted first and second moments.
  constexpr std::size_t kWidth = 10;
  std::vector<double> moments;
  moments.reserve(kWidth * std::size_t(owned));
  for (std::int32_t i = 0; i < owned; ++i) {
    const double a = cells.areas()[i];
    const geom::Vec3& x = position(i);
    moments.insert(moments.end(),
                   {a, a * x[0], a * x[1], a * x[2], a * x[0] * x[0], a * x[0] * x[1],
                    a * x[0] * x[2], a * x[1] * x[1], a * x[1] * x[2], a * x[2] * x[2]});
  }
  // Per cell pair across a region's border: the pair's border length, under the owned cell's
  // label (each pair is summed once per side, as each side's region has that border).
  const auto& stencil = cells.neighbors();
  std::vector<std::int64_t> border_labels;
  std::vector<double> borders;
  for (std::int32_t i = 0; i < owned; ++i)
    for (std::int64_t e = stencil.offsets[i]; e < stencil.offsets[i + 1]; ++e)
      if (labels[i] >= 0 && labels[stencil.indices[e]] != labels[i]) {
        border_labels.push_back(labels[i]);
        borders.push_back(cells.couplings()[e] *
                          (position(i) - position(stencil.indices[e])).norm());
      }
  const auto cell_totals =
      par::labelled_sums_on_root(comm, labels.first(std::size_t(owned)), moments, kWidth);
  const auto border_totals = par::labelled_sums_on_root(comm, border_labels, borders, 1);
  std::vector<RegionMoments> regions;
  std::size_t b = 0;
  for (const auto& total : cell_totals) {
    RegionMoments region{total.label, total.count, total.sums[0], {}, {}, 0.0};
    std::copy(total.sums.begin() + 1, total.sums.begin() + 4, region.first.begin());
    std::copy(total.sums.begin() + 4, total.sums.end(), region.second.begin());
    while (b < border_totals.size() && border_totals[b].label < total.label)
      ++b;
    if (b < border_totals.size() && border_totals[b].label == total.label)
      region.perimeter = border_totals[b].sums[0];
    regions.push_back(region);
  }
  return regions;
}

} // namespace texsim::pipelines::turk_rd
