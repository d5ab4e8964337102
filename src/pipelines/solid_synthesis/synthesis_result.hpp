#pragma once
/// The finished synthesis written out: the exemplar colours that S, cropped to the requested
/// size, selects, as one .vdb and PNG cross-sections assembled on rank 0 as the slabs arrive, and
/// S and the colours written in parallel for ParaView.
#include "pipelines/solid_synthesis/coordinate_slab.hpp"
#include "vol/channel_grid.hpp"

#include <array>
#include <filesystem>
#include <vector>

namespace texsim::pipelines::solid_synthesis {

/// Writes on rank 0, from every rank's planes of the crop as they arrive in z order (rank 0
/// holds the .vdb's sparse tree and one slab at a time, never the whole result):
/// <dir>/solid_synthesis.vdb (a Vec3s grid "colour", or a float grid "density" for scalar
/// exemplars), PNG cross-sections at X = Y = Z = each of `cross_sections` in <dir>/slices, and
/// <dir>/slices/comparison.png, the exemplar's central cross-sections above the result's.
/// Collective; returns the paths written (on rank 0; empty elsewhere).
std::vector<std::filesystem::path>
write_assembled_result(const par::Comm& comm, const std::filesystem::path& dir,
                       const CoordinateSlab& slab, const std::array<int, 3>& dims,
                       const vol::ChannelGrid& exemplar, const std::vector<int>& cross_sections);

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
