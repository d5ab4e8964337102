#pragma once
/// A texture atlas of a triangle surface: disk charts flattened by LSCM, scaled to one texel
/// density and packed into a square image with a gutter around every chart.
///
/// Coordinates. The atlas image has `resolution` x `resolution` texels; texel (x, y) has row y = 0
/// at the top of the image (img::Image's convention) and covers u in [x, x+1] / resolution,
/// v in [resolution-1-y, resolution-y] / resolution, with v = 0 at the bottom as in OBJ files. Its
/// centre is therefore at uv = ((x + 0.5) / resolution, 1 - (y + 0.5) / resolution).
#include "geom/chart_segmentation.hpp"
#include "geom/triangle_mesh.hpp"

#include <Eigen/Core>

#include <array>
#include <cstdint>
#include <vector>

namespace texsim::geom {

/// How build_texture_atlas() cuts and packs.
struct AtlasSettings {
  int resolution = 1024; ///< texels per side of the square atlas (>= 8)
  /// Texels around each chart that still belong to it (>= 0): a texel whose centre is within
  /// `gutter` texels (max-norm) of a chart shows that chart's nearest surface point, so bilinear
  /// filtering inside a chart never reads another chart when gutter >= 1. Charts are kept at
  /// least 2 * gutter + 1 texels apart.
  int gutter = 2;
  std::int32_t max_chart_triangles = 5000;    ///< see ChartSettings
  double max_normal_deviation_degrees = 60.0; ///< see ChartSettings
};

/// Where every triangle corner lies in the atlas.
struct TextureAtlas {
  int resolution = 0; ///< texels per side
  int gutter = 0;     ///< as in AtlasSettings
  /// uv in [0, 1]^2 of each triangle's corners, in the triangle's corner order. Every uv triangle
  /// is counter-clockwise with positive area when the surface is consistently oriented.
  std::vector<std::array<Eigen::Vector2d, 3>> corner_uv;
  std::vector<std::int32_t> chart_of_triangle; ///< 0 .. chart_count-1
  std::int32_t chart_count = 0;
  /// Texels per model unit of length, the same in every chart: each chart's uv area is
  /// (texels_per_unit / resolution)^2 times its surface area.
  double texels_per_unit = 0.0;
};

/// Builds the atlas of `mesh` (manifold, consistently oriented, no zero-area triangles; boundaries
/// and any genus allowed). Charts come from segment_charts(); each is flattened by
/// lscm_parameterize(), and a chart on which LSCM throws, has a triangle whose texel density (uv
/// over surface area) is more than 4 times above or below the chart's (flipped and degenerate
/// triangles included), or whose uv boundary crosses or nearly touches itself (two boundary edges
/// closer in uv than 0.2 times their distance on the surface), is cut by split_chart() and the
/// pieces retried (a single triangle is laid out isometrically). Each chart is rotated to its
/// smallest-area bounding box (lying flat), scaled to the common density, and packed by shelves in
/// order of decreasing height (ties: wider first, then lower chart id) at the largest density that
/// fits. Chart ids follow each chart's smallest triangle id. Deterministic (OpenMP over charts does
/// not change the result). Throws texsim::Error for invalid settings, a zero-area triangle, or when
/// the charts and their gutters cannot fit at any density (resolution too small for the chart
/// count).
TextureAtlas build_texture_atlas(const TriangleMesh& mesh, const AtlasSettings& settings = {});

/// One texel the atlas uses and the surface point its centre shows.
struct AtlasTexel {
  std::int32_t x = 0, y = 0;  ///< column, row (row 0 at the top)
  std::int32_t triangle = -1; ///< triangle of the mesh
  /// Barycentric weights of the point in `triangle`, in its corner order (>= 0, sum 1).
  std::array<double, 3> weights{};
};

/// A rectangle of texels: columns [x0, x1), rows [y0, y1) (row 0 at the top).
struct TexelRect {
  int x0 = 0, y0 = 0, x1 = 0, y1 = 0;
};

/// Every texel the atlas uses, sorted by row then column, each once: a texel whose centre lies in
/// a uv triangle shows that point (on an edge shared by several: the lowest triangle id); a gutter
/// texel (centre outside its chart but within `gutter` texels of it, max-norm) shows the chart
/// point nearest its centre (Euclidean in uv; ties: lowest triangle id), so colours filled in by
/// the caller continue each chart without bleeding into the next. `atlas` must come from
/// build_texture_atlas(mesh, ...). Deterministic; serial.
std::vector<AtlasTexel> atlas_texels(const TriangleMesh& mesh, const TextureAtlas& atlas);

/// atlas_texels() a rectangle at a time, so memory follows the rectangle (a tile of a large atlas)
/// rather than the whole atlas: texels_in(rect) gives exactly the texels of atlas_texels() that lie
/// in `rect`, with the same triangles and weights, in the same order. Keeps a copy of the atlas
/// and each chart's triangles and texel box. texels_in() is const (OpenMP over the charts that
/// touch the rectangle).
class AtlasTexelIndex {
public:
  AtlasTexelIndex(const TriangleMesh& mesh, const TextureAtlas& atlas);
  std::vector<AtlasTexel> texels_in(const TexelRect& rect) const;

private:
  TextureAtlas atlas_;
  std::vector<std::vector<std::int32_t>> charts_; ///< triangles of each chart, increasing ids
  std::vector<TexelRect> chart_boxes_;            ///< texels each chart may claim (a superset)
};

} // namespace texsim::geom
