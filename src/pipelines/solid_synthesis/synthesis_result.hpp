#pragma once
/// The finished synthesis: its colours gathered on rank 0 (the exemplar colours that S, cropped to
/// the requested size, selects) for the .vdb, the slices and the metrics, and S and the colours
/// written in parallel for ParaView.
#include "pipelines/solid_synthesis/coordinate_slab.hpp"
#include "vol/channel_grid.hpp"

#include <array>
#include <filesystem>
#include <vector>

namespace texsim::pipelines::solid_synthesis {

struct SynthesisResult {
  vol::ChannelGrid colours; ///< exemplar colours at S (1 or 3 channels)
};

/// Gathers the finest level's slabs to rank 0, cropped to `dims`, looking up the colours slab by
/// slab as they arrive (rank 0 holds the colours and one slab of S). Collective; only rank 0's
/// result is filled.
SynthesisResult gather_result(const par::Comm& comm, const CoordinateSlab& slab,
                              const std::array<int, 3>& dims, const vol::ChannelGrid& exemplar);

/// Writes (call on rank 0 only): <dir>/solid_synthesis.vdb (a Vec3s grid "colour", or a float
/// grid "density" for scalar exemplars) and PNG cross-sections at X = Y = Z = each of
/// `cross_sections` in <dir>/slices. Returns the paths written.
std::vector<std::filesystem::path> write_result(const std::filesystem::path& dir,
                                                const SynthesisResult& result,
                                                const std::vector<int>& cross_sections);

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
