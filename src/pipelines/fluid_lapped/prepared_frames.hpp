#pragma once
/// The frames of the animation, each made ready once (read, repaired, remeshed, atlas charts
/// flattened and packed) by one rank and then shared: frames are spread round robin, rank r
/// preparing frame k when k mod size == r, all of a batch at once, so the serial per-frame work
/// runs on every rank in parallel ahead of the frame loop that needs it.
#include "geom/texture_atlas.hpp"
#include "par/comm.hpp"
#include "pipelines/fluid_lapped/fluid_frames.hpp"
#include "pipelines/fluid_lapped/fluid_lapped_settings.hpp"

#include <functional>
#include <map>
#include <optional>

namespace texsim::pipelines::fluid_lapped {

/// A frame ready for the patches: its surface (with the velocity at its vertices when the input
/// carries one) and its atlas.
struct PreparedFrame {
  FluidFrame frame;
  geom::TextureAtlas atlas;
};

/// The atlas of a flat square mesh in a plane z = const: uv = (x - x0, y - y0) / side, one chart,
/// so the atlas image is an orthographic rendering of the square. Throws InputError naming
/// `fluid_lapped.atlas.layout` when the mesh is not flat in z or its extent is not square.
geom::TextureAtlas planar_atlas(const geom::TriangleMesh& mesh, int resolution, int gutter);

/// The atlas of `mesh` as `settings.layout` says.
geom::TextureAtlas frame_atlas(const geom::TriangleMesh& mesh, const AtlasSettings& settings);

class PreparedFrames {
public:
  /// `read(k)` gives frame k's surface and velocity (serial; called on the preparing rank only).
  PreparedFrames(const par::Comm& comm, int frame_count, std::function<FluidFrame(int)> read,
                 AtlasSettings atlas);

  /// Frame k on every rank. Collective: every rank asks for the same k, in increasing order.
  /// Errors of the preparing rank (a bad file) are raised on every rank.
  PreparedFrame get(int k);

private:
  par::Comm comm_;
  int frame_count_;
  std::function<FluidFrame(int)> read_;
  AtlasSettings atlas_;
  int batch_begin_ = -1;              ///< first frame of the batch prepared last
  std::optional<PreparedFrame> mine_; ///< the frame this rank prepared in that batch
};

} // namespace texsim::pipelines::fluid_lapped
