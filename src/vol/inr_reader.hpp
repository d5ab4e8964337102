#pragma once
/// INRIMAGE-4 volumes (.inr): a text header "#INRIMAGE-4#{" of KEY=VALUE lines padded to a
/// multiple of 256 bytes and closed by "##}", followed by the raw voxels, x fastest, VDIM values
/// interleaved per voxel.
#include "vol/dense_grid.hpp"

#include <filesystem>

namespace texsim::vol {

/// Reads an INRIMAGE-4 file: XDIM, YDIM, ZDIM (required), VDIM 1 (-> ScalarGrid) or 3 (-> RgbGrid),
/// TYPE float (PIXSIZE 32 or 64 bits) or unsigned/signed fixed (8, 16 or 32 bits; raw integer
/// values converted to float, not rescaled), CPU byte order (decm/alpha/pc little-endian,
/// sun/sgi big-endian), VX/VY/VZ voxel spacing (default 1). Throws InputError naming the file and
/// the field if the header is malformed, or the byte counts if the voxel data is truncated.
AnyGrid read_inr(const std::filesystem::path& path);

} // namespace texsim::vol
