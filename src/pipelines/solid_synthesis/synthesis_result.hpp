#pragma once
/// The finished synthesis written out: the exemplar colours that S, cropped to the requested
/// size, selects, as one .vdb every rank writes its planes into, PNG cross-sections, and S and
/// the colours written in parallel for ParaView.
#include "core/stage_timers.hpp"
#include "pipelines/solid_synthesis/coordinate_slab.hpp"
#include "vol/channel_grid.hpp"
#include "vol/vdb_dense_layout.hpp"

#include <array>
#include <filesystem>
#include <vector>

namespace texsim::pipelines::solid_synthesis {

/// Writes <dir>/solid_synthesis.vdb (a Vec3s grid "colour", or a float grid "density" for scalar
/// exemplars, its leaves stored with `compression`) from every rank's planes of the crop at once
/// (vol/parallel_vdb_writer.hpp: no rank holds more than its planes and 7 more); and PNG
/// cross-sections at X = Y = Z = each of `cross_sections` in <dir>/slices and
/// <dir>/slices/comparison.png (the exemplar's central cross-sections above the result's), each set
/// taken by every rank from its own planes, summed onto one writer rank after rank 0 and written
/// there. Times its parts as stages "colouring" (every rank its planes), "vdb" (every rank its
/// leaves, rank 0 also the tree's structure) and "slices" (the PNGs). Collective; returns the paths
/// written (on rank 0; empty elsewhere).
std::vector<std::filesystem::path>
write_volume_and_sections(const par::Comm& comm, const std::filesystem::path& dir,
                          const CoordinateSlab& slab, const std::array<int, 3>& dims,
                          const vol::ChannelGrid& exemplar, const std::vector<int>& cross_sections,
                          vol::VdbCompression compression, StageTimers& timers);

/// Writes the result for ParaView in parallel, every rank its own slab cropped to `dims` (plus
/// the next slab's first plane, which VTK pieces share): <dir>/solid_synthesis.pvti (the colour or
/// density) and <dir>/exemplar_coordinates.pvti (S, to re-colour with another channel of the
/// exemplar), their pieces in folders of the same names. The slab's halo must be current.
/// Collective; returns the .pvti paths.
std::vector<std::filesystem::path> write_parallel_result(const par::Comm& comm,
                                                         const std::filesystem::path& dir,
                                                         const CoordinateSlab& slab,
                                                         const std::array<int, 3>& dims,
                                                         const vol::ChannelGrid& exemplar);

} // namespace texsim::pipelines::solid_synthesis
