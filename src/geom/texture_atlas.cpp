#include "geom/texture_atlas.hpp"

#include "core/error.hpp"
#include "geom/lscm_parameterization.hpp"
#include "geom/mesh_measures.hpp"
#include "geom/mesh_topology.hpp"
#include "geom/submesh.hpp"

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <exception>
#include <limits>
#include <numbers>
#include <optional>
#include <span>
#include <tuple>

namespace texsim::geom {
namespace {

using Vec2 = Eigen::Vector2d;
using CornerUv = std::array<Vec2, 3>;

/// Twice the signed area of (a, b, c): positive when counter-clockwise.
double orient(const Vec2& a, const Vec2& b, const Vec2& c) {
  const Vec2 u = b - a;
  const Vec2 v = c - a;
  return u.x() * v.y() - u.y() * v.x();
}

/// Distance between the segments pq and rs, in any dimension (closest points by clamped
/// parameters, Ericson's "Real-Time Collision Detection" 5.1.9).
template <class Vec>
double segment_distance(const Vec& p, const Vec& q, const Vec& r, const Vec& s) {
  const Vec d1 = q - p, d2 = s - r, offset = p - r;
  const double a = d1.squaredNorm(), e = d2.squaredNorm(), f = d2.dot(offset);
  double along1 = 0.0, along2 = 0.0;
  if (a == 0.0 && e == 0.0) {
    return offset.norm();
  }
  if (a == 0.0) {
    along2 = std::clamp(f / e, 0.0, 1.0);
  } else {
    const double c = d1.dot(offset);
    if (e == 0.0) {
      along1 = std::clamp(-c / a, 0.0, 1.0);
    } else {
      const double b = d1.dot(d2), denominator = a * e - b * b;
      along1 = denominator > 0.0 ? std::clamp((b * f - c * e) / denominator, 0.0, 1.0) : 0.0;
      along2 = (b * along1 + f) / e;
      if (along2 < 0.0) {
        along2 = 0.0;
        along1 = std::clamp(-c / a, 0.0, 1.0);
      } else if (along2 > 1.0) {
        along2 = 1.0;
        along1 = std::clamp((b - c) / a, 0.0, 1.0);
      }
    }
  }
  return ((p + along1 * d1) - (r + along2 * d2)).norm();
}

/// One chart laid out in the plane, in model units (uv area = surface area).
struct FlatChart {
  std::vector<std::int32_t> triangles; ///< increasing ids
  std::vector<CornerUv> corner_uv;     ///< per chart triangle
};

/// The triangle laid out with its own edge lengths, counter-clockwise.
CornerUv isometric_layout(const TriangleMesh& mesh, std::int32_t t) {
  const auto& tri = mesh.triangles[t];
  const Vec3 ab = mesh.positions[tri[1]] - mesh.positions[tri[0]];
  const Vec3 ac = mesh.positions[tri[2]] - mesh.positions[tri[0]];
  const double length = ab.norm();
  TEXSIM_VERIFY(length > 0.0 && ab.cross(ac).norm() > 0.0,
                "build_texture_atlas: triangle " << t << " has zero area");
  const double along = ab.dot(ac) / length;
  const double across = ab.cross(ac).norm() / length;
  return {Vec2(0.0, 0.0), Vec2(length, 0.0), Vec2(along, across)};
}

/// Whether the chart's uv boundary crosses itself or nearly touches itself: two boundary edges
/// without a common vertex closer in uv than kNarrowGap times their distance on the surface (uv
/// in model units, the chart's area kept). Across such a slit a gutter texel could show a point
/// far from the one its neighbours show; a crossing overlaps the map although no triangle flips.
bool boundary_pinches(const MeshTopology& topology, const std::vector<Vec2>& uv,
                      const std::vector<Vec3>& positions) {
  constexpr double kNarrowGap = 0.2;
  const auto& boundary = topology.boundary_edges();
  const auto& edges = topology.edges();
  for (std::size_t i = 0; i < boundary.size(); ++i) {
    const Edge& a = edges[boundary[i]];
    for (std::size_t j = i + 1; j < boundary.size(); ++j) {
      const Edge& b = edges[boundary[j]];
      if (a[0] == b[0] || a[0] == b[1] || a[1] == b[0] || a[1] == b[1]) {
        continue;
      }
      const double in_uv = segment_distance(uv[a[0]], uv[a[1]], uv[b[0]], uv[b[1]]);
      if (in_uv < kNarrowGap * segment_distance(positions[a[0]], positions[a[1]], positions[b[0]],
                                                positions[b[1]])) {
        return true;
      }
    }
  }
  return false;
}

/// Largest ratio between a triangle's texel density (uv area over surface area) and its chart's.
constexpr double kMaxAreaDistortion = 4.0;

/// LSCM of the chart scaled to the surface's area, or nothing when LSCM fails or its map is not
/// usable (a triangle's density off by more than kMaxAreaDistortion, flipped and degenerate ones
/// included, or a boundary that crosses or nearly touches itself).
std::optional<FlatChart> flatten(const TriangleMesh& mesh, std::vector<std::int32_t> triangles) {
  FlatChart chart;
  chart.triangles = std::move(triangles);
  if (chart.triangles.size() == 1) {
    chart.corner_uv.push_back(isometric_layout(mesh, chart.triangles.front()));
    return chart;
  }
  const Submesh sub = extract_triangles(mesh, chart.triangles);
  std::vector<Vec2> uv;
  try {
    uv = lscm_parameterize(sub.mesh);
  } catch (const Error&) {
    return std::nullopt;
  }
  double surface_area = 0.0;
  double uv_area = 0.0;
  std::vector<double> areas(sub.mesh.triangles.size());
  std::vector<double> uv_areas(sub.mesh.triangles.size());
  for (std::size_t t = 0; t < sub.mesh.triangles.size(); ++t) {
    const auto& tri = sub.mesh.triangles[t];
    areas[t] = triangle_area(sub.mesh.positions[tri[0]], sub.mesh.positions[tri[1]],
                             sub.mesh.positions[tri[2]]);
    uv_areas[t] = 0.5 * orient(uv[tri[0]], uv[tri[1]], uv[tri[2]]);
    surface_area += areas[t];
    uv_area += uv_areas[t];
  }
  if (!(std::isfinite(uv_area) && uv_area > 0.0 && surface_area > 0.0)) {
    return std::nullopt;
  }
  // Texel density may vary by kMaxAreaDistortion either way around the chart's mean; a flipped or
  // degenerate triangle is far outside.
  const double ratio = uv_area / surface_area;
  for (std::size_t t = 0; t < areas.size(); ++t) {
    if (!(uv_areas[t] * kMaxAreaDistortion >= ratio * areas[t] &&
          uv_areas[t] <= kMaxAreaDistortion * ratio * areas[t])) {
      return std::nullopt;
    }
  }
  const double scale = std::sqrt(surface_area / uv_area);
  for (Vec2& p : uv) {
    p *= scale;
  }
  if (boundary_pinches(MeshTopology(sub.mesh), uv, sub.mesh.positions)) {
    return std::nullopt;
  }
  for (const auto& tri : sub.mesh.triangles) {
    chart.corner_uv.push_back({uv[tri[0]], uv[tri[1]], uv[tri[2]]});
  }
  return chart;
}

/// Charts of the segmentation flattened, unusable ones split and retried, ordered by their
/// smallest triangle id.
std::vector<FlatChart> flatten_charts(const TriangleMesh& mesh, const AtlasSettings& settings) {
  const ChartSegmentation segmentation =
      segment_charts(mesh, {settings.max_chart_triangles, settings.max_normal_deviation_degrees});
  std::vector<std::vector<std::int32_t>> pending(segmentation.chart_count);
  for (std::int32_t t = 0; t < mesh.num_triangles(); ++t) {
    pending[segmentation.chart_of_triangle[t]].push_back(t);
  }
  const MeshTopology topology(mesh);
  std::vector<FlatChart> done;
  while (!pending.empty()) {
    const auto count = static_cast<std::int64_t>(pending.size());
    std::vector<std::optional<FlatChart>> flat(pending.size());
    std::vector<std::exception_ptr> failure(pending.size());
#pragma omp parallel for schedule(dynamic)
    for (std::int64_t i = 0; i < count; ++i) {
      try {
        flat[i] = flatten(mesh, pending[i]);
      } catch (...) {
        failure[i] = std::current_exception();
      }
    }
    std::vector<std::vector<std::int32_t>> retry;
    for (std::size_t i = 0; i < pending.size(); ++i) {
      if (failure[i]) {
        std::rethrow_exception(failure[i]);
      }
      if (flat[i]) {
        done.push_back(std::move(*flat[i]));
      } else {
        for (auto& piece : split_chart(mesh, topology, pending[i])) {
          retry.push_back(std::move(piece));
        }
      }
    }
    pending = std::move(retry);
  }
  std::sort(done.begin(), done.end(), [](const FlatChart& a, const FlatChart& b) {
    return a.triangles.front() < b.triangles.front();
  });
  return done;
}

/// Convex hull of `points`, counter-clockwise (Andrew's monotone chain).
std::vector<Vec2> convex_hull(std::vector<Vec2> points) {
  std::sort(points.begin(), points.end(), [](const Vec2& a, const Vec2& b) {
    return std::tie(a.x(), a.y()) < std::tie(b.x(), b.y());
  });
  std::vector<Vec2> hull(2 * points.size());
  std::size_t k = 0;
  for (std::size_t i = 0; i < points.size(); ++i) {
    while (k >= 2 && orient(hull[k - 2], hull[k - 1], points[i]) <= 0) {
      --k;
    }
    hull[k++] = points[i];
  }
  for (std::size_t i = points.size() - 1, lower = k + 1; i-- > 0;) {
    while (k >= lower && orient(hull[k - 2], hull[k - 1], points[i]) <= 0) {
      --k;
    }
    hull[k++] = points[i];
  }
  hull.resize(k > 1 ? k - 1 : k);
  return hull;
}

/// Rotates the chart so that its bounding box has the smallest area (some hull edge lies along
/// it) and is at least as wide as high, then moves the box's lower-left corner to the origin.
/// Returns the box size.
Vec2 lay_flat(FlatChart& chart) {
  std::vector<Vec2> points;
  for (const auto& corners : chart.corner_uv) {
    points.insert(points.end(), corners.begin(), corners.end());
  }
  const std::vector<Vec2> hull = convex_hull(points);
  const auto box_of = [&](const Eigen::Matrix2d& rotation) {
    Eigen::AlignedBox2d box;
    for (const Vec2& p : hull) {
      box.extend(rotation * p);
    }
    return box;
  };
  Eigen::Matrix2d best = Eigen::Matrix2d::Identity();
  double best_area = box_of(best).volume();
  for (std::size_t i = 0; i < hull.size(); ++i) {
    const Vec2 edge = hull[(i + 1) % hull.size()] - hull[i];
    if (edge.norm() == 0.0) {
      continue;
    }
    const double angle = -std::atan2(edge.y(), edge.x());
    const Eigen::Matrix2d rotation = Eigen::Rotation2Dd(angle).toRotationMatrix();
    const double area = box_of(rotation).volume();
    if (area < best_area) {
      best_area = area;
      best = rotation;
    }
  }
  Eigen::AlignedBox2d box = box_of(best);
  if (box.sizes().y() > box.sizes().x()) {
    best = Eigen::Rotation2Dd(std::numbers::pi / 2).toRotationMatrix() * best;
    box = box_of(best);
  }
  for (auto& corners : chart.corner_uv) {
    for (Vec2& p : corners) {
      p = best * p - box.min();
    }
  }
  return box.sizes();
}

/// Lower-left texel corner of each chart's cell in the atlas (x right, y up, texel units).
using CellCorners = std::vector<Eigen::Vector2i>;

/// Shelf packing of the charts' cells at `texels_per_unit`: cells in `order` left to right, a new
/// shelf above the highest cell of the last one when the row is full. Nothing when the cells do
/// not fit in the resolution x resolution square.
std::optional<CellCorners> pack(const std::vector<Vec2>& sizes,
                                const std::vector<std::size_t>& order, double texels_per_unit,
                                int resolution, int gutter) {
  CellCorners corners(sizes.size());
  const auto cell = [&](double extent) {
    return static_cast<std::int64_t>(std::ceil(extent * texels_per_unit)) + 2 * gutter + 1;
  };
  std::int64_t x = 0, y = 0, shelf = 0;
  for (const std::size_t c : order) {
    const std::int64_t width = cell(sizes[c].x());
    const std::int64_t height = cell(sizes[c].y());
    if (x + width > resolution) {
      y += shelf;
      x = 0;
      shelf = 0;
    }
    if (width > resolution || y + height > resolution) {
      return std::nullopt;
    }
    corners[c] = Eigen::Vector2i(static_cast<int>(x), static_cast<int>(y));
    x += width;
    shelf = std::max(shelf, height);
  }
  return corners;
}

} // namespace

TextureAtlas build_texture_atlas(const TriangleMesh& mesh, const AtlasSettings& settings) {
  TEXSIM_VERIFY(settings.resolution >= 8 && settings.resolution <= (1 << 16),
                "build_texture_atlas: resolution must be in [8, 65536], got "
                    << settings.resolution);
  TEXSIM_VERIFY(settings.gutter >= 0 && settings.gutter < settings.resolution / 4,
                "build_texture_atlas: gutter must be in [0, resolution/4), got "
                    << settings.gutter);
  TEXSIM_VERIFY(mesh.num_triangles() > 0, "build_texture_atlas: the mesh has no triangles");

  std::vector<FlatChart> charts = flatten_charts(mesh, settings);
  std::vector<Vec2> sizes;
  for (FlatChart& chart : charts) {
    sizes.push_back(lay_flat(chart));
  }
  std::vector<std::size_t> order(charts.size());
  for (std::size_t c = 0; c < order.size(); ++c) {
    order[c] = c;
  }
  std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
    return std::make_tuple(-sizes[a].y(), -sizes[a].x(), a) <
           std::make_tuple(-sizes[b].y(), -sizes[b].x(), b);
  });

  // The largest density at which everything fits, by bisection: fitting at density 0 means the
  // gutters alone fit; above resolution / (largest extent) the largest chart alone does not.
  const int resolution = settings.resolution;
  const int gutter = settings.gutter;
  TEXSIM_VERIFY(pack(sizes, order, 0.0, resolution, gutter),
                "build_texture_atlas: " << charts.size() << " charts with a gutter of " << gutter
                                        << " texels do not fit in a " << resolution << " x "
                                        << resolution << " atlas; raise the resolution");
  double largest = 0.0;
  for (const Vec2& size : sizes) {
    largest = std::max(largest, size.maxCoeff());
  }
  double low = 0.0;
  double high = resolution / largest;
  for (int step = 0; step < 60; ++step) {
    const double middle = 0.5 * (low + high);
    (pack(sizes, order, middle, resolution, gutter) ? low : high) = middle;
  }
  TEXSIM_VERIFY(low > 0.0, "build_texture_atlas: no positive texel density fits the "
                               << resolution << " x " << resolution << " atlas");
  const CellCorners cells = *pack(sizes, order, low, resolution, gutter);

  TextureAtlas atlas;
  atlas.resolution = resolution;
  atlas.gutter = gutter;
  atlas.texels_per_unit = low;
  atlas.chart_count = static_cast<std::int32_t>(charts.size());
  atlas.corner_uv.resize(mesh.triangles.size());
  atlas.chart_of_triangle.assign(mesh.triangles.size(), -1);
  const double margin = gutter + 0.5;
  for (std::size_t c = 0; c < charts.size(); ++c) {
    const Vec2 origin = cells[c].cast<double>() + Vec2(margin, margin);
    for (std::size_t i = 0; i < charts[c].triangles.size(); ++i) {
      const std::int32_t t = charts[c].triangles[i];
      atlas.chart_of_triangle[t] = static_cast<std::int32_t>(c);
      for (int corner = 0; corner < 3; ++corner) {
        atlas.corner_uv[t][corner] = (origin + low * charts[c].corner_uv[i][corner]) / resolution;
      }
    }
  }
  return atlas;
}

namespace {

/// The point of triangle (a, b, c) nearest p, as barycentric weights, and its squared distance.
std::pair<std::array<double, 3>, double> nearest_in_triangle(const Vec2& p, const Vec2& a,
                                                             const Vec2& b, const Vec2& c) {
  const double area = orient(a, b, c);
  const std::array<double, 3> inside{orient(p, b, c) / area, orient(a, p, c) / area,
                                     orient(a, b, p) / area};
  if (inside[0] >= 0.0 && inside[1] >= 0.0 && inside[2] >= 0.0) {
    return {inside, 0.0};
  }
  const std::array<Vec2, 3> corner{a, b, c};
  std::array<double, 3> best_weights{};
  double best = std::numeric_limits<double>::infinity();
  for (int side = 0; side < 3; ++side) {
    const int from = (side + 1) % 3, to = (side + 2) % 3; // edge opposite corner `side`
    const Vec2 edge = corner[to] - corner[from];
    const double along = std::clamp((p - corner[from]).dot(edge) / edge.squaredNorm(), 0.0, 1.0);
    const double distance = (corner[from] + along * edge - p).squaredNorm();
    if (distance < best) {
      best = distance;
      best_weights = {};
      best_weights[from] = 1.0 - along;
      best_weights[to] = along;
    }
  }
  return {best_weights, best};
}

/// Whether the axis-aligned square of half-side `half` around p meets triangle (a, b, c)
/// (separating axes: the square's two and the triangle's three edge normals).
bool square_meets_triangle(const Vec2& p, double half, const std::array<Vec2, 3>& corner) {
  const auto separated = [&](const Vec2& axis) {
    const double centre = axis.dot(p);
    const double reach = half * (std::abs(axis.x()) + std::abs(axis.y()));
    double low = std::numeric_limits<double>::infinity();
    double high = -low;
    for (const Vec2& q : corner) {
      low = std::min(low, axis.dot(q));
      high = std::max(high, axis.dot(q));
    }
    return low > centre + reach || high < centre - reach;
  };
  if (separated(Vec2::UnitX()) || separated(Vec2::UnitY())) {
    return false;
  }
  for (int side = 0; side < 3; ++side) {
    const Vec2 edge = corner[(side + 1) % 3] - corner[side];
    if (separated(Vec2(-edge.y(), edge.x()))) {
      return false;
    }
  }
  return true;
}

/// The texels of one chart (its triangles in increasing id order) inside `clip`, in any order.
std::vector<AtlasTexel> chart_texels(const TextureAtlas& atlas,
                                     std::span<const std::int32_t> triangles,
                                     const TexelRect& clip) {
  const int resolution = atlas.resolution;
  const double gutter = atlas.gutter;
  // Texel (x, y) has its centre at (x + 0.5, resolution - y - 0.5) in texel units with v up.
  const auto texel_space = [&](const Vec2& uv) { return Vec2(uv * resolution); };
  Eigen::AlignedBox2d box;
  for (const std::int32_t t : triangles) {
    for (const Vec2& uv : atlas.corner_uv[t]) {
      box.extend(texel_space(uv));
    }
  }
  const int x0 = std::max(clip.x0, static_cast<int>(std::ceil(box.min().x() - gutter - 0.5)));
  const int x1 = std::min(clip.x1 - 1, static_cast<int>(std::floor(box.max().x() + gutter - 0.5)));
  const int y0 =
      std::max(clip.y0, static_cast<int>(std::ceil(resolution - 0.5 - box.max().y() - gutter)));
  const int y1 = std::min(clip.y1 - 1,
                          static_cast<int>(std::floor(resolution - 0.5 - box.min().y() + gutter)));
  if (x1 < x0 || y1 < y0) {
    return {};
  }
  const int width = x1 - x0 + 1;

  struct Best {
    double distance = std::numeric_limits<double>::infinity(); ///< squared, texel units
    std::int32_t triangle = -1;
    std::array<double, 3> weights{};
    bool member = false;
  };
  std::vector<Best> best(static_cast<std::size_t>(width) * (y1 - y0 + 1));
  // A member texel is within `gutter` of its chart in max-norm, so its Euclidean-nearest point
  // is within sqrt(2) * gutter: triangles farther away cannot be the nearest of any member.
  const double reach = std::sqrt(2.0) * gutter + 1.0;
  for (const std::int32_t t : triangles) {
    const std::array<Vec2, 3> corner{texel_space(atlas.corner_uv[t][0]),
                                     texel_space(atlas.corner_uv[t][1]),
                                     texel_space(atlas.corner_uv[t][2])};
    Eigen::AlignedBox2d near;
    for (const Vec2& q : corner) {
      near.extend(q);
    }
    const int tx0 = std::max(x0, static_cast<int>(std::ceil(near.min().x() - reach - 0.5)));
    const int tx1 = std::min(x1, static_cast<int>(std::floor(near.max().x() + reach - 0.5)));
    const int ty0 =
        std::max(y0, static_cast<int>(std::ceil(resolution - 0.5 - near.max().y() - reach)));
    const int ty1 =
        std::min(y1, static_cast<int>(std::floor(resolution - 0.5 - near.min().y() + reach)));
    for (int y = ty0; y <= ty1; ++y) {
      for (int x = tx0; x <= tx1; ++x) {
        Best& slot = best[static_cast<std::size_t>(y - y0) * width + (x - x0)];
        // Inside an earlier triangle: no later one is nearer, and the texel is a member.
        if (slot.distance == 0.0) {
          continue;
        }
        const Vec2 centre(x + 0.5, resolution - y - 0.5);
        const auto [weights, distance] =
            nearest_in_triangle(centre, corner[0], corner[1], corner[2]);
        // Triangles come in increasing id order: a tie keeps the lower id.
        if (distance < slot.distance) {
          slot.distance = distance;
          slot.triangle = t;
          slot.weights = weights;
        }
        slot.member =
            slot.member || distance == 0.0 || square_meets_triangle(centre, gutter, corner);
      }
    }
  }
  std::vector<AtlasTexel> texels;
  for (int y = y0; y <= y1; ++y) {
    for (int x = x0; x <= x1; ++x) {
      const Best& slot = best[static_cast<std::size_t>(y - y0) * width + (x - x0)];
      if (slot.member) {
        texels.push_back({x, y, slot.triangle, slot.weights});
      }
    }
  }
  return texels;
}

} // namespace

AtlasTexelIndex::AtlasTexelIndex(const TriangleMesh& mesh, const TextureAtlas& atlas)
    : atlas_(atlas), charts_(std::size_t(atlas.chart_count)) {
  TEXSIM_VERIFY(atlas.corner_uv.size() == mesh.triangles.size() &&
                    atlas.chart_of_triangle.size() == mesh.triangles.size(),
                "atlas_texels: the atlas has " << atlas.corner_uv.size() << " triangles, the mesh "
                                               << mesh.triangles.size());
  for (std::int32_t t = 0; t < mesh.num_triangles(); ++t)
    charts_[std::size_t(atlas.chart_of_triangle[std::size_t(t)])].push_back(t);
  // Each chart's texel box grown by the gutter: the texels it may claim.
  for (const auto& chart : charts_) {
    Eigen::AlignedBox2d box;
    for (const std::int32_t t : chart)
      for (const Vec2& uv : atlas.corner_uv[std::size_t(t)])
        box.extend(Vec2(uv * atlas.resolution));
    const double g = atlas.gutter + 1.0;
    chart_boxes_.push_back({int(std::floor(box.min().x() - g)),
                            int(std::floor(atlas.resolution - box.max().y() - g)),
                            int(std::ceil(box.max().x() + g)) + 1,
                            int(std::ceil(atlas.resolution - box.min().y() + g)) + 1});
  }
}

std::vector<AtlasTexel> AtlasTexelIndex::texels_in(const TexelRect& rect) const {
  std::vector<std::int32_t> touching;
  for (std::size_t c = 0; c < charts_.size(); ++c) {
    const auto& box = chart_boxes_[c];
    if (box.x0 < rect.x1 && rect.x0 < box.x1 && box.y0 < rect.y1 && rect.y0 < box.y1)
      touching.push_back(std::int32_t(c));
  }
  std::vector<std::vector<AtlasTexel>> per_chart(touching.size());
  const auto count = static_cast<std::int64_t>(touching.size());
#pragma omp parallel for schedule(dynamic)
  for (std::int64_t i = 0; i < count; ++i)
    per_chart[std::size_t(i)] =
        chart_texels(atlas_, charts_[std::size_t(touching[std::size_t(i)])], rect);
  // Row-major order by placing each texel at its place in the rectangle (no sort: the charts'
  // texels are clipped to it), which also finds a texel claimed twice.
  const auto width = std::size_t(std::max(0, rect.x1 - rect.x0));
  const auto height = std::size_t(std::max(0, rect.y1 - rect.y0));
  std::vector<std::pair<std::int32_t, std::int32_t>> at(width * height, {-1, -1});
  std::size_t count_found = 0;
  for (std::size_t c = 0; c < per_chart.size(); ++c) {
    for (std::size_t i = 0; i < per_chart[c].size(); ++i) {
      const AtlasTexel& texel = per_chart[c][i];
      auto& place = at[std::size_t(texel.y - rect.y0) * width + std::size_t(texel.x - rect.x0)];
      TEXSIM_VERIFY(place.first < 0, "atlas_texels: texel (" << texel.x << ", " << texel.y
                                                             << ") claimed by two charts");
      place = {std::int32_t(c), std::int32_t(i)};
      ++count_found;
    }
  }
  std::vector<AtlasTexel> texels;
  texels.reserve(count_found);
  for (const auto& [chart, i] : at) {
    if (chart >= 0) {
      texels.push_back(per_chart[std::size_t(chart)][std::size_t(i)]);
    }
  }
  return texels;
}

std::vector<AtlasTexel> atlas_texels(const TriangleMesh& mesh, const TextureAtlas& atlas) {
  return AtlasTexelIndex(mesh, atlas).texels_in({0, 0, atlas.resolution, atlas.resolution});
}

} // namespace texsim::geom
