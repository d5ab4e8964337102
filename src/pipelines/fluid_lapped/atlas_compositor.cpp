#include "pipelines/fluid_lapped/atlas_compositor.hpp"

#include "core/error.hpp"
#include "geom/mesh_measures.hpp"
#include "par/record_exchange.hpp"

#include <mpi.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <tuple>

namespace texsim::pipelines::fluid_lapped {
namespace {

using Point2 = Eigen::Vector2d;

/// Image coordinates of a surface point q near frame triangle t, through t's affine map into
/// its chart (q projected into t's plane, barycentric weights not clamped).
Point2 image_point(const geom::TriangleMesh& frame, const geom::TextureAtlas& atlas, std::int32_t t,
                   const geom::Vec3& q) {
  const auto& tri = frame.triangles[std::size_t(t)];
  const auto w = geom::barycentric_weights(frame.positions[std::size_t(tri[0])],
                                           frame.positions[std::size_t(tri[1])],
                                           frame.positions[std::size_t(tri[2])], q);
  const auto& corner = atlas.corner_uv[std::size_t(t)];
  const Point2 uv = w[0] * corner[0] + w[1] * corner[1] + w[2] * corner[2];
  return {uv.x() * atlas.resolution, atlas.resolution * (1.0 - uv.y())};
}

using SeamNeighbours = std::vector<std::vector<std::pair<std::int32_t, std::int32_t>>>;

/// The frame triangle whose map places vertex v of `patch` in `chart`: its own surface triangle
/// when that lies in the chart, else, of the chart's triangles sharing a corner with it, the one
/// that holds the vertex best (largest smallest barycentric weight; ties: first listed), so a
/// vertex on a seam maps exactly where the chart has it. -1 when the chart is not next to it.
std::int32_t map_triangle_for(const geom::TriangleMesh& frame, const geom::TextureAtlas& atlas,
                              const SeamNeighbours& across_seam, const Patch& patch, std::size_t v,
                              std::int32_t chart) {
  const auto surface = patch.surface_triangle[v];
  if (atlas.chart_of_triangle[std::size_t(surface)] == chart)
    return surface;
  std::int32_t best = -1;
  double best_inside = -std::numeric_limits<double>::infinity();
  for (const auto& [other_chart, other] : across_seam[std::size_t(surface)]) {
    if (other_chart != chart)
      continue;
    const auto& tri = frame.triangles[std::size_t(other)];
    const auto w = geom::barycentric_weights(
        frame.positions[std::size_t(tri[0])], frame.positions[std::size_t(tri[1])],
        frame.positions[std::size_t(tri[2])], patch.positions[v]);
    const double inside = std::min({w[0], w[1], w[2]});
    if (inside > best_inside) {
      best_inside = inside;
      best = other;
    }
  }
  return best;
}

/// Triangle `index` of `patch` drawn into every chart its corners lie in and every chart across
/// a seam next to a corner's triangle (in order of first mention). Each corner is mapped by its
/// own map_triangle_for() triangle, so neighbouring patch triangles share their corners' images
/// and leave no cracks; a corner with none in that chart borrows the triangle of the first
/// corner that has one (the chart's map extended).
std::vector<MappedTriangle> map_triangle(const geom::TriangleMesh& frame,
                                         const geom::TextureAtlas& atlas,
                                         const SeamNeighbours& across_seam, const Patch& patch,
                                         std::size_t index) {
  const auto& corners = patch.triangles[index];
  std::vector<std::int32_t> charts;
  for (int c = 0; c < 3; ++c) {
    const auto surface = patch.surface_triangle[std::size_t(corners[std::size_t(c)])];
    charts.push_back(atlas.chart_of_triangle[std::size_t(surface)]);
    for (const auto& [chart, triangle] : across_seam[std::size_t(surface)])
      charts.push_back(chart);
  }
  std::vector<MappedTriangle> mapped;
  for (const auto chart : charts) {
    if (std::any_of(mapped.begin(), mapped.end(),
                    [&](const MappedTriangle& m) { return m.chart == chart; }))
      continue;
    std::array<std::int32_t, 3> through{};
    std::int32_t fallback = -1;
    for (int k = 0; k < 3; ++k) {
      through[std::size_t(k)] = map_triangle_for(frame, atlas, across_seam, patch,
                                                 std::size_t(corners[std::size_t(k)]), chart);
      if (fallback < 0)
        fallback = through[std::size_t(k)];
    }
    MappedTriangle m;
    m.patch = patch.id;
    m.triangle = std::int32_t(index);
    m.chart = chart;
    for (int k = 0; k < 3; ++k) {
      const auto v = std::size_t(corners[std::size_t(k)]);
      const auto t = through[std::size_t(k)] >= 0 ? through[std::size_t(k)] : fallback;
      const Point2 xy = image_point(frame, atlas, t, patch.positions[v]);
      m.xy[k][0] = xy.x();
      m.xy[k][1] = xy.y();
      m.uv[k][0] = patch.rest_uv[v].x();
      m.uv[k][1] = patch.rest_uv[v].y();
      m.weight[k] = patch.weights[v];
    }
    mapped.push_back(m);
  }
  std::sort(mapped.begin(), mapped.end(),
            [](const MappedTriangle& a, const MappedTriangle& b) { return a.chart < b.chart; });
  return mapped;
}

/// The sample of `m` at a texel's sample point: nullopt when the point is outside the mapped
/// triangle (a degenerate image counts as outside) or the patch texel there is eroded.
std::optional<TexelSample> sample_at(const MappedTriangle& m, const std::array<float, 2>& point,
                                     const ErosionMask& erosion) {
  const Point2 a(m.xy[0][0], m.xy[0][1]), b(m.xy[1][0], m.xy[1][1]), c(m.xy[2][0], m.xy[2][1]);
  const Point2 p(point[0], point[1]);
  const auto orient = [](const Point2& o, const Point2& s, const Point2& t) {
    return (s.x() - o.x()) * (t.y() - o.y()) - (s.y() - o.y()) * (t.x() - o.x());
  };
  const double area = orient(a, b, c);
  if (std::abs(area) < 1e-12)
    return std::nullopt;
  const double beta[3] = {orient(p, b, c) / area, orient(a, p, c) / area, orient(a, b, p) / area};
  // A small tolerance closes the cracks between neighbouring triangles' images.
  constexpr double kEdgeTolerance = 1e-9;
  if (beta[0] < -kEdgeTolerance || beta[1] < -kEdgeTolerance || beta[2] < -kEdgeTolerance)
    return std::nullopt;
  Point2 uv = Point2::Zero();
  double weight = 0;
  for (int k = 0; k < 3; ++k) {
    uv += beta[k] * Point2(m.uv[k][0], m.uv[k][1]);
    weight += beta[k] * m.weight[k];
  }
  if (erosion.eroded(uv, weight))
    return std::nullopt;
  return TexelSample{m.patch, float(uv.x()), float(uv.y())};
}

/// Where an atlas texel samples the patches: its centre when the centre lies in its chart, else
/// (a gutter texel) the image of the chart point it shows, moved 1e-3 texel into its triangle:
/// that point lies on the chart's border, where the float it is stored in could round it out of
/// the patch triangles drawn up to the border.
std::array<float, 2> sample_point(const geom::TextureAtlas& atlas, const geom::AtlasTexel& texel) {
  const auto& corner = atlas.corner_uv[std::size_t(texel.triangle)];
  const auto image = [&](const Point2& uv) {
    return Point2(uv.x() * atlas.resolution, atlas.resolution * (1.0 - uv.y()));
  };
  const Point2 at = image(texel.weights[0] * corner[0] + texel.weights[1] * corner[1] +
                          texel.weights[2] * corner[2]);
  const Point2 centre(texel.x + 0.5, texel.y + 0.5);
  if ((at - centre).norm() < 1e-6)
    return {float(centre.x()), float(centre.y())};
  const Point2 inward = image((corner[0] + corner[1] + corner[2]) / 3.0) - at;
  const Point2 inside = at + 1e-3 * inward / std::max(inward.norm(), 1e-3);
  return {float(inside.x()), float(inside.y())};
}

/// Texels whose centres may lie in the image of m: [x0, x1) x [y0, y1).
geom::TexelRect texel_box(const MappedTriangle& m) {
  double lo[2] = {m.xy[0][0], m.xy[0][1]}, hi[2] = {lo[0], lo[1]};
  for (int k = 1; k < 3; ++k)
    for (int d = 0; d < 2; ++d) {
      lo[d] = std::min(lo[d], m.xy[k][d]);
      hi[d] = std::max(hi[d], m.xy[k][d]);
    }
  const auto first = [](double v) { return int(std::ceil(v - 0.5 - 1e-9)); };
  const auto last = [](double v) { return int(std::floor(v - 0.5 + 1e-9)) + 1; };
  return {first(lo[0]), first(lo[1]), last(hi[0]), last(hi[1])};
}

/// The texels that may sample a point of m's image: texel_box(m) grown on every side by the
/// farthest a gutter texel samples from its centre. That is its chart's nearest point, within
/// `gutter` texels in max-norm of the centre but up to sqrt(2) x gutter texels away (1.21 x
/// gutter in max-norm along a border slanted by 22.5 degrees), plus a texel for rounding.
geom::TexelRect sampling_box(const MappedTriangle& m, int gutter) {
  const auto box = texel_box(m);
  const int margin = int(std::ceil(std::sqrt(2.0) * gutter)) + 1;
  return {box.x0 - margin, box.y0 - margin, box.x1 + margin, box.y1 + margin};
}

} // namespace

AtlasCompositor::AtlasCompositor(const par::Comm& comm, const FrameSurface& frame,
                                 const geom::TextureAtlas& atlas, int tile_size,
                                 const ErosionMask& erosion)
    : comm_(comm), frame_(frame.mesh), atlas_(atlas), index_(frame.mesh, atlas),
      resolution_(atlas.resolution), tile_size_(tile_size), erosion_(erosion) {
  TEXSIM_VERIFY(tile_size > 0, "atlas tile size must be positive");
  across_seam_.resize(frame_.triangles.size());
  for (std::int32_t t = 0; t < frame_.num_triangles(); ++t) {
    auto& across = across_seam_[std::size_t(t)];
    for (const auto corner : frame_.triangles[std::size_t(t)])
      for (const auto other : frame.topology.vertex_triangles().row(corner)) {
        const auto chart = atlas.chart_of_triangle[std::size_t(other)];
        if (chart != atlas.chart_of_triangle[std::size_t(t)] &&
            std::none_of(across.begin(), across.end(),
                         [&](const auto& known) { return known.second == other; }))
          across.emplace_back(chart, other);
      }
  }
  const int tiles = tile_count_per_side() * tile_count_per_side();
  for (int t = comm.rank; t < tiles; t += comm.size) {
    Tile tile;
    tile.rect = tile_rect(t);
    const int width = tile.rect.x1 - tile.rect.x0;
    const auto count = std::size_t(width) * std::size_t(tile.rect.y1 - tile.rect.y0);
    tile.chart.assign(count, -1);
    tile.triangle.assign(count, -1);
    tile.samples.assign(count, TexelSample{kUnusedTexel, 0, 0});
    tile.sample_points.assign(count, {0.0f, 0.0f});
    for (const auto& texel : index_.texels_in(tile.rect)) {
      const auto i = std::size_t(texel.y - tile.rect.y0) * std::size_t(width) +
                     std::size_t(texel.x - tile.rect.x0);
      tile.chart[i] = atlas.chart_of_triangle[std::size_t(texel.triangle)];
      tile.triangle[i] = texel.triangle;
      tile.samples[i].patch = kUncoveredTexel;
      tile.sample_points[i] = sample_point(atlas, texel);
    }
    tiles_.push_back(std::move(tile));
    tile_ids_.push_back(t);
  }
}

geom::TexelRect AtlasCompositor::tile_rect(int tile) const {
  const int per_side = tile_count_per_side();
  const int tx = tile % per_side, ty = tile / per_side;
  return {tx * tile_size_, ty * tile_size_, std::min(resolution_, (tx + 1) * tile_size_),
          std::min(resolution_, (ty + 1) * tile_size_)};
}

void AtlasCompositor::composite(std::span<const Patch> local_patches) {
  // Route every mapped triangle to the owners of the tiles its texel box touches.
  std::vector<std::vector<MappedTriangle>> outgoing(std::size_t(comm_.size));
  const int per_side = tile_count_per_side();
  for (const auto& patch : local_patches)
    for (std::size_t i = 0; i < patch.triangles.size(); ++i)
      for (auto& m : map_triangle(frame_, atlas_, across_seam_, patch, i)) {
        const auto box = sampling_box(m, atlas_.gutter);
        const int tx0 = std::max(0, box.x0) / tile_size_,
                  tx1 = (std::min(resolution_, box.x1) - 1) / tile_size_;
        const int ty0 = std::max(0, box.y0) / tile_size_,
                  ty1 = (std::min(resolution_, box.y1) - 1) / tile_size_;
        if (box.x1 <= 0 || box.y1 <= 0 || box.x0 >= resolution_ || box.y0 >= resolution_)
          continue;
        for (int ty = ty0; ty <= ty1; ++ty)
          for (int tx = tx0; tx <= tx1; ++tx) {
            m.tile = ty * per_side + tx;
            outgoing[std::size_t(owner_of_tile(m.tile))].push_back(m);
          }
      }
  auto received = par::exchange_records(comm_, outgoing);

  // A tile at a time (so the working slots follow one tile, not all of this rank's), per texel
  // the best (patch, triangle) of this call; committed when the tile is done, so the arrival
  // order of the records does not matter.
  std::sort(received.begin(), received.end(),
            [](const MappedTriangle& a, const MappedTriangle& b) { return a.tile < b.tile; });
  struct Best {
    std::int64_t patch = std::numeric_limits<std::int64_t>::max();
    std::int32_t triangle = 0;
    float u = 0, v = 0;
  };
  std::vector<Best> slots;
  for (auto first = received.begin(); first != received.end();) {
    const auto last = std::find_if(first, received.end(),
                                   [&](const MappedTriangle& m) { return m.tile != first->tile; });
    const auto at = std::lower_bound(tile_ids_.begin(), tile_ids_.end(), first->tile);
    auto& tile = tiles_[std::size_t(at - tile_ids_.begin())];
    const int width = tile.rect.x1 - tile.rect.x0;
    slots.assign(tile.samples.size(), Best{});
    for (const auto& m : std::span(first, last)) {
      const auto box = sampling_box(m, atlas_.gutter);
      for (int y = std::max(box.y0, tile.rect.y0); y < std::min(box.y1, tile.rect.y1); ++y)
        for (int x = std::max(box.x0, tile.rect.x0); x < std::min(box.x1, tile.rect.x1); ++x) {
          const auto i =
              std::size_t(y - tile.rect.y0) * std::size_t(width) + std::size_t(x - tile.rect.x0);
          if (tile.samples[i].patch != kUncoveredTexel || tile.chart[i] != m.chart)
            continue;
          auto& slot = slots[i];
          if (std::tie(m.patch, m.triangle) >= std::tie(slot.patch, slot.triangle))
            continue;
          if (const auto sample = sample_at(m, tile.sample_points[i], erosion_))
            slot = {m.patch, m.triangle, sample->u, sample->v};
        }
    }
    for (std::size_t i = 0; i < slots.size(); ++i)
      if (slots[i].patch != std::numeric_limits<std::int64_t>::max())
        tile.samples[i] = {slots[i].patch, slots[i].u, slots[i].v};
    first = last;
  }
}

PatchImage AtlasCompositor::image_of(const Patch& patch) const {
  PatchImage image;
  for (std::size_t i = 0; i < patch.triangles.size(); ++i)
    for (const auto& m : map_triangle(frame_, atlas_, across_seam_, patch, i))
      image.triangles.push_back(m);
  return image;
}

std::vector<std::int32_t> AtlasCompositor::covered_texels(const PatchImage& image,
                                                          const UncoveredTexelIndex& index,
                                                          std::int32_t from) const {
  std::vector<char> hit(index.texels().size(), 0);
  for (const auto& m : image.triangles)
    index.for_each_inside(sampling_box(m, atlas_.gutter), [&](std::int32_t i) {
      const auto& texel = index.texels()[std::size_t(i)];
      if (i >= from && !hit[std::size_t(i)] && texel.chart == m.chart &&
          sample_at(m, texel.image, erosion_))
        hit[std::size_t(i)] = 1;
    });
  std::vector<std::int32_t> covered;
  for (std::size_t i = std::size_t(from); i < hit.size(); ++i)
    if (hit[i])
      covered.push_back(std::int32_t(i));
  return covered;
}

std::vector<UncoveredTexel> AtlasCompositor::first_uncovered(std::size_t max_count) const {
  // Each rank's first max_count uncovered texels, then the first of all ranks'.
  struct Found {
    std::int64_t index; ///< y * resolution + x
    std::int32_t chart, triangle;
    std::array<float, 2> image;
  };
  std::vector<Found> mine;
  for (const auto& tile : tiles_) {
    const int width = tile.rect.x1 - tile.rect.x0;
    std::size_t found = 0;
    for (std::size_t i = 0; i < tile.samples.size() && found < max_count; ++i)
      if (tile.samples[i].patch == kUncoveredTexel) {
        mine.push_back({std::int64_t(tile.rect.y0 + int(i) / width) * resolution_ + tile.rect.x0 +
                            int(i) % width,
                        tile.chart[i], tile.triangle[i], tile.sample_points[i]});
        ++found;
      }
  }
  const auto earlier = [](const Found& a, const Found& b) { return a.index < b.index; };
  std::sort(mine.begin(), mine.end(), earlier);
  if (mine.size() > max_count)
    mine.resize(max_count);
  auto all = par::allgather_records(comm_, mine);
  std::sort(all.begin(), all.end(), earlier);
  if (all.size() > max_count)
    all.resize(max_count);
  std::vector<UncoveredTexel> uncovered;
  for (const auto& found : all) {
    // The surface point under the texel's sample point, through its triangle's uv image.
    const auto& corner = atlas_.corner_uv[std::size_t(found.triangle)];
    const auto image = [&](const Point2& uv) {
      return Point2(uv.x() * resolution_, resolution_ * (1.0 - uv.y()));
    };
    const Point2 a = image(corner[0]), b = image(corner[1]), c = image(corner[2]);
    const Point2 p(found.image[0], found.image[1]);
    const auto cross = [](const Point2& u, const Point2& v) {
      return u.x() * v.y() - u.y() * v.x();
    };
    const double area = cross(b - a, c - a);
    const double wb = cross(p - a, c - a) / area, wc = cross(b - a, p - a) / area;
    const auto& tri = frame_.triangles[std::size_t(found.triangle)];
    const geom::Vec3 position = (1 - wb - wc) * frame_.positions[std::size_t(tri[0])] +
                                wb * frame_.positions[std::size_t(tri[1])] +
                                wc * frame_.positions[std::size_t(tri[2])];
    uncovered.push_back({int(found.index % resolution_),
                         int(found.index / resolution_),
                         found.chart,
                         {position, found.triangle},
                         found.image});
  }
  return uncovered;
}

void AtlasCompositor::mark_unreachable(int x, int y) {
  const int per_side = tile_count_per_side();
  const int tile = (y / tile_size_) * per_side + x / tile_size_;
  if (owner_of_tile(tile) != comm_.rank)
    return;
  const auto at = std::lower_bound(tile_ids_.begin(), tile_ids_.end(), tile);
  auto& t = tiles_[std::size_t(at - tile_ids_.begin())];
  auto& sample = t.samples[std::size_t(y - t.rect.y0) * std::size_t(t.rect.x1 - t.rect.x0) +
                           std::size_t(x - t.rect.x0)];
  if (sample.patch == kUncoveredTexel)
    sample.patch = kUnreachableTexel;
}

std::vector<std::int64_t> AtlasCompositor::winning_patches() const {
  std::vector<std::int64_t> mine;
  for (const auto& tile : tiles_)
    for (const auto& sample : tile.samples)
      if (sample.patch >= 0)
        mine.push_back(sample.patch);
  std::sort(mine.begin(), mine.end());
  mine.erase(std::unique(mine.begin(), mine.end()), mine.end());
  auto all = par::allgather_records(comm_, mine);
  std::sort(all.begin(), all.end());
  all.erase(std::unique(all.begin(), all.end()), all.end());
  return all;
}

AtlasCoverage AtlasCompositor::coverage() const {
  std::int64_t counts[3] = {0, 0, 0};
  for (const auto& tile : tiles_)
    for (const auto& sample : tile.samples) {
      counts[0] += sample.patch != kUnusedTexel;
      counts[1] += sample.patch >= 0;
      counts[2] += sample.patch == kUnreachableTexel;
    }
  MPI_Allreduce(MPI_IN_PLACE, counts, 3, MPI_INT64_T, MPI_SUM, comm_.raw);
  return {counts[0], counts[1], counts[2]};
}

std::vector<TexelSample> AtlasCompositor::rows(int first_row, int last_row) const {
  TEXSIM_VERIFY(0 <= first_row && first_row <= last_row && last_row <= resolution_,
                "atlas rows " << first_row << " .. " << last_row - 1 << " asked of "
                              << resolution_);
  std::vector<int> asked(2 * std::size_t(comm_.size));
  const int mine[2] = {first_row, last_row};
  MPI_Allgather(mine, 2, MPI_INT, asked.data(), 2, MPI_INT, comm_.raw);
  // A tile's part of rows [first, last), row after row; sender and receiver walk the same tiles.
  const auto each_row = [](const geom::TexelRect& rect, int first, int last, auto&& visit) {
    for (int y = std::max(first, rect.y0); y < std::min(last, rect.y1); ++y)
      visit(y);
  };
  std::vector<std::vector<TexelSample>> outgoing(std::size_t(comm_.size));
  for (int r = 0; r < comm_.size; ++r)
    for (const auto& tile : tiles_) {
      const auto width = std::size_t(tile.rect.x1 - tile.rect.x0);
      each_row(tile.rect, asked[2 * std::size_t(r)], asked[2 * std::size_t(r) + 1], [&](int y) {
        const auto row =
            tile.samples.begin() + std::ptrdiff_t(std::size_t(y - tile.rect.y0) * width);
        outgoing[std::size_t(r)].insert(outgoing[std::size_t(r)].end(), row,
                                        row + std::ptrdiff_t(width));
      });
    }
  const auto received = par::exchange_records(comm_, outgoing);
  std::vector<TexelSample> strip(std::size_t(last_row - first_row) * std::size_t(resolution_));
  auto from = received.begin();
  const int tiles = tile_count_per_side() * tile_count_per_side();
  for (int owner = 0; owner < comm_.size; ++owner)
    for (int t = 0; t < tiles; ++t) {
      if (owner_of_tile(t) != owner)
        continue;
      const auto rect = tile_rect(t);
      const auto width = std::ptrdiff_t(rect.x1 - rect.x0);
      each_row(rect, first_row, last_row, [&](int y) {
        std::copy(from, from + width,
                  strip.begin() +
                      std::ptrdiff_t(std::size_t(y - first_row) * std::size_t(resolution_) +
                                     std::size_t(rect.x0)));
        from += width;
      });
    }
  return strip;
}

} // namespace texsim::pipelines::fluid_lapped
