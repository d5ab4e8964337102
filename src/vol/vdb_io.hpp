#pragma once
/// Dense grids to and from OpenVDB files (.vdb): scalar grids as openvdb::FloatGrid, colour grids
/// as openvdb::Vec3SGrid, voxel (0, 0, 0) at index (0, 0, 0), and a scale-translate transform from
/// the grid's spacing and origin.
///
/// Sparsity: voxels exactly equal to the background (0) become inactive background, so the file
/// stays small for mostly empty volumes; the dense dims are stored in the grid metadata
/// "texsim_dense_dims" (and the exact spacing and origin in "texsim_spacing", "texsim_origin"),
/// so reading restores the grid exactly. Grids written elsewhere (no such metadata) are read over
/// the bounding box of their active voxels, with spacing and origin from their transform.
#include "vol/channel_grid.hpp"
#include "vol/dense_grid.hpp"

#include <array>
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

namespace texsim::vol {

/// Writes `grid` as the only grid of a new .vdb file, replacing any file at `path` atomically
/// (core/atomic_output.hpp). Throws Error naming the file if it cannot be written, leaving a file
/// already at `path` as it was.
void write_vdb(const std::filesystem::path& path, const ScalarGrid& grid,
               const std::string& grid_name);
void write_vdb(const std::filesystem::path& path, const RgbGrid& grid,
               const std::string& grid_name);
/// The same for a grid of 1 channel (a float grid) or 3 (a Vec3s grid), spacing 1 and origin 0,
/// without a copy as a DenseGrid.
void write_vdb(const std::filesystem::path& path, const ChannelGrid& grid,
               const std::string& grid_name);

/// Reads the grid called `grid_name` (or, if empty, the first FloatGrid or Vec3SGrid in the file)
/// into a dense ScalarGrid or RgbGrid. Throws InputError naming the file if it is missing or not a
/// readable VDB file, has no grid of that name (the message lists the grids it has), the grid is
/// neither float nor Vec3s, has no active voxels, or its transform is not axis-aligned.
AnyGrid read_vdb(const std::filesystem::path& path, const std::string& grid_name = "");

/// A triangle surface as plain arrays (vol does not know geom): world positions, and corner
/// indices turned counter-clockwise seen from outside.
struct LevelSetSurface {
  std::vector<std::array<double, 3>> positions;
  std::vector<std::array<std::int32_t, 3>> triangles;
};

/// The zero crossing of the FloatGrid level set `grid_name` (negative inside) of a .vdb file,
/// meshed by OpenVDB's volumeToMesh without adaptivity, quads split along one diagonal: a fluid
/// simulator's surface. InputError naming the file for a missing grid, another grid type or no
/// crossing.
LevelSetSurface read_level_set_surface(const std::filesystem::path& path,
                                       const std::string& grid_name);

} // namespace texsim::vol
