#pragma once
/// What fluid_lapped writes for every frame, each a ParaView series (.pvd) or a numbered image:
///   surface.pvd       the frame's surface split at chart seams, `uv` as texture coordinates,
///                     `velocity` (surface/surface_<k>.pvtp)
///   atlas/atlas_<k>.png               the frame's texture atlas
///   displacement/displacement_<k>.png 16-bit grey, when the exemplar has a displacement image
///   patch_ids.pvd     per texel: winning patch id (-1 uncovered, -2 unused), its age in frames
///                     and its uv (patch_ids/patch_ids_<k>.pvti, one .vti piece per strip)
///   patches.pvd       the patch meshes with `patch_id` and the erosion weight `w`
///                     (patches/patches_<k>.pvtp)
/// The atlas images are cut into strips of tile rows, an even share of the strips per rank: each
/// rank colours and compresses its own strips (io/parallel_png_writer.hpp) and writes their .vti
/// pieces; rank k mod size writes frame k's PNG files from the compressed bytes.
#include "io/pvd_series.hpp"
#include "par/comm.hpp"
#include "pipelines/fluid_lapped/atlas_compositor.hpp"
#include "pipelines/fluid_lapped/erosion_mask.hpp"
#include "pipelines/fluid_lapped/fluid_exemplar.hpp"
#include "pipelines/fluid_lapped/prepared_frames.hpp"
#include "pipelines/fluid_lapped/velocity_field.hpp"

#include <cstdint>
#include <filesystem>
#include <optional>
#include <span>
#include <vector>

namespace texsim::pipelines::fluid_lapped {

class FrameOutputs {
public:
  /// Starts the series in `output_dir`, or continues them after `restart_time` (the time of
  /// the last frame the checkpoint holds). Collective.
  /// `exemplar` and `erosion` (which maps a patch uv to its exemplar texel) must outlive this.
  FrameOutputs(const par::Comm& comm, std::filesystem::path output_dir,
               const FluidExemplar& exemplar, const ErosionMask& erosion,
               std::optional<double> restart_time);

  /// Writes frame k. `velocity` gives the surface's velocity where the frame has none at its
  /// vertices (analytic flows; may be null). Collective.
  void write(int k, double time, const PreparedFrame& frame, const AtlasCompositor& compositor,
             std::span<const Patch> patches, const VelocityField* velocity);

  /// The .pvd files, for summary.json.
  std::vector<std::filesystem::path> series() const;

private:
  void write_surface(int k, double time, const PreparedFrame& frame, const VelocityField* velocity);
  void write_patches(int k, double time, std::span<const Patch> patches);
  void write_atlas(int k, double time, const AtlasCompositor& compositor,
                   std::span<const Patch> patches);

  /// Every patch's birth frame, sorted by id, on every rank (for the ages).
  struct Birth {
    std::int64_t id;
    std::int32_t frame;
  };
  std::vector<Birth> births(std::span<const Patch> patches) const;

  par::Comm comm_;
  std::filesystem::path dir_;
  const FluidExemplar& exemplar_;
  const ErosionMask& erosion_;
  io::PvdSeries surface_, patches_, ids_;
  std::vector<std::uint8_t> exemplar_rgb8_;     ///< 3 bytes per exemplar texel
  std::vector<std::uint8_t> exemplar_height16_; ///< 2 bytes (big-endian) per texel, or none
};

} // namespace texsim::pipelines::fluid_lapped
