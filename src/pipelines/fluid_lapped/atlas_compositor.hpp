#pragma once
/// Lapped-texture compositing into one frame's atlas (section 5.1): per texel, the covering
/// patches oldest (lowest id) first; the first whose texel there is not eroded gives the texel its
/// patch and patch uv. No blending.
///
/// Distributed by tiles: the atlas is cut into tile x tile squares, tile i (row-major) owned by
/// rank i mod size, and only the owner stores a tile's texels. Patch triangles are mapped into the
/// atlas through the positions of their vertices on the frame's surface (each corner's frame
/// triangle and its chart's affine map; a triangle spanning charts is drawn into each of them by
/// the local extension of that chart's map; so is one whose corner lies on a triangle next to a
/// seam, into the charts across it, which covers the gutter there) and sent to the owners of the
/// tiles their texel boxes touch. No per-texel tree queries.
#include "geom/surface_point.hpp"
#include "geom/texture_atlas.hpp"
#include "par/comm.hpp"
#include "pipelines/fluid_lapped/erosion_mask.hpp"
#include "pipelines/fluid_lapped/frame_surface.hpp"
#include "pipelines/fluid_lapped/patch.hpp"
#include "pipelines/fluid_lapped/uncovered_texel_index.hpp"

#include <array>
#include <cstdint>
#include <span>
#include <vector>

namespace texsim::pipelines::fluid_lapped {

/// What one texel shows.
struct TexelSample {
  std::int64_t patch = -2; ///< patch id, or one of the constants below
  float u = 0, v = 0;      ///< the patch's rest uv at the texel centre
};
inline constexpr std::int64_t kUnusedTexel = -2;      ///< no chart claims the texel
inline constexpr std::int64_t kUncoveredTexel = -1;   ///< no patch covers it (yet)
inline constexpr std::int64_t kUnreachableTexel = -3; ///< given up: its own new patch missed it

/// A patch triangle drawn into one chart: its corners in image coordinates (x right, y down,
/// texel (x, y) covering [x, x + 1] x [y, y + 1]) with the rest uv and weight at each corner.
struct MappedTriangle {
  std::int64_t patch = 0;
  std::int32_t triangle = 0; ///< index in the patch
  std::int32_t chart = 0;
  std::int32_t tile = 0; ///< the tile this copy is for (routing)
  double xy[3][2] = {};
  double uv[3][2] = {};
  double weight[3] = {};
};

/// A patch drawn into the atlas (every triangle in every chart it reaches, triangles in order),
/// to ask patch_sample() about many texels.
struct PatchImage {
  std::vector<MappedTriangle> triangles;
};

/// Texel counts over the whole atlas.
struct AtlasCoverage {
  std::int64_t used = 0, covered = 0, unreachable = 0;
};

class AtlasCompositor {
public:
  /// `frame` and `atlas` (geom::build_texture_atlas of frame.mesh, or a planar atlas) are the
  /// same on every rank; `frame` and `erosion` must outlive the compositor. Collective (each rank
  /// sets up its tiles).
  AtlasCompositor(const par::Comm& comm, const FrameSurface& frame, const geom::TextureAtlas& atlas,
                  int tile_size, const ErosionMask& erosion);

  /// Adds patches below all those composited so far: a texel still uncovered takes, among the
  /// patches of all ranks in this call, the lowest id whose sample there (patch_sample) is not
  /// eroded. Texels covered earlier never change. Any split of the patches over ranks gives the
  /// same texels. Collective.
  void composite(std::span<const Patch> local_patches);

  /// Up to max_count uncovered used texels in atlas order (row-major, row 0 at the top), with the
  /// surface points they show; the same on every rank. Collective.
  std::vector<UncoveredTexel> first_uncovered(std::size_t max_count) const;

  /// Marks an uncovered texel as given up. Call on every rank with the same texel.
  void mark_unreachable(int x, int y);

  /// The texels of `index` from position `from` on that a patch drawn by image_of would cover if
  /// it lay alone on the surface (composite() of it alone would give them the patch): those in a
  /// chart the image reaches with a triangle holding the texel's sample point where the patch is
  /// not eroded. Positions in index.texels(), increasing. Not collective; any rank.
  std::vector<std::int32_t> covered_texels(const PatchImage& image,
                                           const UncoveredTexelIndex& index,
                                           std::int32_t from = 0) const;

  /// `patch` drawn into the atlas as composite() draws it. Not collective.
  PatchImage image_of(const Patch& patch) const;

  /// Ids of the patches that own at least one texel, sorted; the same on every rank. Collective.
  std::vector<std::int64_t> winning_patches() const;

  /// Used, covered and unreachable texels of the whole atlas. Collective.
  AtlasCoverage coverage() const;

  /// Rows first_row .. last_row - 1 of the atlas on this rank (row-major, row 0 at the top,
  /// resolution samples a row), each rank asking for its own rows (any, overlapping or none).
  /// Every tile owner sends the asked-for rows of its tiles. Collective.
  std::vector<TexelSample> rows(int first_row, int last_row) const;

  int resolution() const { return resolution_; }
  int tile_size() const { return tile_size_; }

private:
  struct Tile {
    geom::TexelRect rect;
    std::vector<std::int32_t> chart;    ///< per texel of rect, -1 when unused
    std::vector<std::int32_t> triangle; ///< the frame triangle each texel shows
    std::vector<TexelSample> samples;   ///< per texel of rect
    /// Where each texel samples the patches, in image coordinates: its centre, or for a gutter
    /// texel the nearest point of its chart, so gutters continue their chart.
    std::vector<std::array<float, 2>> sample_points;
  };

  int tile_count_per_side() const { return (resolution_ + tile_size_ - 1) / tile_size_; }
  geom::TexelRect tile_rect(int tile) const;
  int owner_of_tile(int tile) const { return tile % comm_.size; }

  par::Comm comm_;
  const geom::TriangleMesh& frame_;
  const geom::TextureAtlas& atlas_;
  geom::AtlasTexelIndex index_;
  int resolution_, tile_size_;
  const ErosionMask& erosion_;
  /// For each frame triangle at a chart seam, the triangles of other charts sharing a corner
  /// with it, as (chart, triangle): a patch triangle near a seam is also drawn into the charts
  /// across it, so the gutter texels there are covered.
  std::vector<std::vector<std::pair<std::int32_t, std::int32_t>>> across_seam_;
  std::vector<Tile> tiles_;   ///< this rank's tiles, in increasing tile order
  std::vector<int> tile_ids_; ///< their tile numbers
};

} // namespace texsim::pipelines::fluid_lapped
