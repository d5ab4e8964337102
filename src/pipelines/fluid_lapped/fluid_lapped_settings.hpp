#pragma once
/// The `fluid_lapped:` config section (Gagnon et al. 2021), read into typed settings; see
/// config/fluid_lapped/*.yaml and docs/fluid_lapped.md for every key.
#include "core/config.hpp"
#include "geom/mesh_source.hpp"
#include "pipelines/fluid_lapped/analytic_flows.hpp"
#include "pipelines/fluid_lapped/fluid_frames.hpp"

#include <filesystem>
#include <optional>

namespace texsim::pipelines::fluid_lapped {

/// Where the animated surface and its velocity come from: simulator files, or one fixed surface
/// carried by an analytic flow (CI and the tests).
struct FrameSettings {
  /// count: frames to process (a run-length key: a finished run continues with a larger one);
  /// 0 = every frame the files list (files only)
  int count = 0;
  /// files: surfaces, interval, velocity_array or velocity_grids (+ grid_array), edge_length
  std::optional<FrameSourceSettings> files;
  /// analytic: mesh (a MeshSource section), flow, interval
  geom::MeshSource mesh;
  AnalyticFlowSettings flow;
  double interval = 0.05; ///< interval: time between analytic frames
};

struct ExemplarSettings {
  std::filesystem::path image;        ///< image: PNG, JPEG or GIMP .pat
  std::filesystem::path feature_map;  ///< feature_map: grey image, same size (empty: luminance)
  std::filesystem::path displacement; ///< displacement: grey image carried like the colour
};

/// How the per-frame atlas is laid out.
enum class AtlasLayout {
  charts, ///< Levy 2002: disk charts flattened by LSCM, packed (any surface)
  planar, ///< uv = (x, y) / size over a flat square: the atlas is an orthographic rendering
};

struct AtlasSettings {
  int resolution = 1024; ///< resolution: texels per side (up to 6144 in the paper)
  int gutter = 2;        ///< gutter: texels around every chart
  int tile = 256;        ///< tile: texels per side of a compositing tile (ranks own tiles)
  AtlasLayout layout = AtlasLayout::charts;
  std::int32_t max_chart_triangles = 5000;    ///< max_chart_triangles
  double max_normal_deviation_degrees = 60.0; ///< max_normal_deviation
};

struct FluidLappedSettings {
  FrameSettings frames;
  ExemplarSettings exemplar;
  double radius = 0;          ///< radius: patch radius r, model units (required)
  double delta_max = 3.0;     ///< erosion.delta_max: distortion at which a triangle's quality is 0
  double epsilon = 0.1;       ///< erosion.epsilon: how much every patch is eroded from the start
  AtlasSettings atlas;        ///< atlas
  int creation_batch = 64;    ///< creation_batch: new-patch candidates built per round
  int substep_multiplier = 1; ///< advection.substep_multiplier: RK4 substeps times this
};

FluidLappedSettings read_fluid_lapped_settings(const ConfigSection& section);

} // namespace texsim::pipelines::fluid_lapped
