#pragma once
/// The ParaView series of a run, `surface_synthesis.pvd`: one entry per level and pass (time =
/// 2 x levels synthesised before + pass), each the level's retiled mesh with its colours, texture
/// direction s and owning rank; ParaView steps through the synthesis from coarse to fine.
#include "io/pvd_series.hpp"
#include "pipelines/surface_synthesis/level_synthesizer.hpp"
#include "pipelines/surface_synthesis/mesh_pyramid.hpp"

#include <filesystem>
#include <optional>

namespace texsim::pipelines::surface_synthesis {

class LevelFrames {
public:
  /// A new series, or after a restart the series continued before `restart_time`. Collective.
  LevelFrames(const par::Comm& comm, const std::filesystem::path& output_dir,
              std::optional<double> restart_time);

  /// Series time of `pass` on `level` of a `levels`-level pyramid.
  static double time_of(int levels, int level, Pass pass) {
    return 2.0 * (levels - 1 - level) + double(pass);
  }

  /// Writes `level` of a `levels`-level pyramid after `pass` (each rank the triangles whose
  /// smallest vertex it owns; `directions` and `colours` of the rank's run, the other corners'
  /// fetched from their owners) and adds it to the series. Collective.
  void write(int levels, int level, Pass pass, const RetiledLevel& retiled,
             std::span<const geom::Vec3> directions, const LevelColours& colours);

  const std::filesystem::path& path() const { return series_.path(); }

private:
  par::Comm comm_;
  std::filesystem::path output_dir_;
  io::PvdSeries series_;
};

} // namespace texsim::pipelines::surface_synthesis
