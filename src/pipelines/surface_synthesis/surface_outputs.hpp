#pragma once
/// What a finished synthesis leaves besides the level series: the colour carried back onto the
/// input mesh M_s (Wei-Levoy Section 5: "the output can be mapped back onto the original model in
/// a postprocess by resampling"), a texture atlas of it with an OBJ that references it, and, with
/// displacement.scale > 0, the input mesh displaced by the synthesised luminance (Fig. 9's
/// mannequin).
#include "img/image.hpp"
#include "par/comm.hpp"
#include "pipelines/surface_synthesis/level_synthesizer.hpp"
#include "pipelines/surface_synthesis/mesh_pyramid.hpp"
#include "pipelines/surface_synthesis/surface_synthesis_settings.hpp"

#include <filesystem>
#include <vector>

namespace texsim::pipelines::surface_synthesis {

struct SurfaceOutputs {
  std::vector<std::filesystem::path> files;
  /// Colour histogram distance between the finest level's vertices and the exemplar's pixels.
  double histogram_distance = 0;
};

/// Writes surface.pvtp (M_s with `color`), atlas.png + textured.obj/.mtl (atlas.resolution > 0)
/// and displaced.pvtp (displacement.scale > 0) into `output_dir`. Rank 0 does the work on its
/// `surface` (M_s is rank 0's alone; the others pass an empty mesh) with the finest level's
/// colours gathered from every rank's run (`colours`); errors reach every rank. Collective.
SurfaceOutputs write_surface_outputs(const par::Comm& comm, const geom::TriangleMesh& surface,
                                     const RetiledLevel& finest, const LevelColours& colours,
                                     const img::RgbImage& exemplar,
                                     const SurfaceSynthesisSettings& settings,
                                     const std::filesystem::path& output_dir);

} // namespace texsim::pipelines::surface_synthesis
