#pragma once
/// A dense volume split in z over ranks, written as one .vdb by every rank at once: the layout of
/// vol/vdb_dense_layout.hpp (a FloatGrid or Vec3SGrid, every voxel active) lets each rank turn
/// its own planes into leaf records and write them where they go (MPI-IO, par/parallel_file.hpp)
/// while rank 0 writes the header and the tree's structure. A leaf whose 8 planes straddle two
/// ranks is made by the rank holding its first plane, which receives the rest (at most 7 planes)
/// from the ranks above. Uncompressed, every record has the same size and its offset follows
/// from its block; compressed, every rank measures its records first and rank 0, which needs
/// every leaf's size for the head's delayed-load table anyway, lays them out in file order and
/// sends each rank its offsets.
///
/// No rank holds more than its planes, 7 more and the records of 32 planes (rank 0 also six
/// 8-byte integers a leaf while laying out compressed leaves), and no message carries more than 7
/// planes. The file's bytes do not depend on the rank count: its UUID is derived from the leaf
/// records (par/positional_checksum.hpp), so the same volume gives the same file. read_vdb
/// (vol/vdb_io.hpp) and OpenVDB's own reader (ParaView, Houdini) read it.
#include "par/comm.hpp"
#include "vol/dense_grid.hpp"
#include "vol/vdb_dense_layout.hpp"

#include <filesystem>
#include <string>
#include <vector>

namespace texsim::vol {

/// This rank's planes z_first, z_first + 1, ... (whole x-y planes of `dims`, x fastest,
/// `channels` floats a voxel; none is allowed) of a volume whose ranks' planes follow each other
/// in rank order and cover it once. Writes `path` atomically as the grid `grid_name`, its leaf
/// values stored with `compression`. Collective; an error on any rank is raised on all, naming
/// `path`.
void write_parallel_vdb(const par::Comm& comm, const std::filesystem::path& path, Dims dims,
                        int channels, int z_first, std::vector<float> planes,
                        const std::string& grid_name, VdbCompression compression);

} // namespace texsim::vol
