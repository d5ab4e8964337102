#include "pipelines/solid_synthesis/synthesis_result.hpp"

#include "core/error.hpp"
#include "par/gather_to_root.hpp"
#include "vol/cross_section_writer.hpp"
#include "vol/parallel_vti_writer.hpp"
#include "vol/vdb_io.hpp"

#include <algorithm>
#include <cstring>
#include <optional>
#include <string>

namespace texsim::pipelines::solid_synthesis {
namespace {

/// The owned voxels of `slab` inside the crop box, plane by plane, x fastest.
std::vector<Coord> cropped_owned(const CoordinateSlab& slab, const std::array<int, 3>& dims) {
  const LevelLayout& layout = slab.layout();
  std::vector<Coord> out;
  const int z_end = std::min(layout.z_end, dims[2]);
  for (int k = layout.z_begin; k < z_end; ++k)
    for (int j = 0; j < dims[1]; ++j)
      for (int i = 0; i < dims[0]; ++i)
        out.push_back(slab.at(i, j, k));
  return out;
}

} // namespace

SynthesisResult gather_result(const par::Comm& comm, const CoordinateSlab& slab,
                              const std::array<int, 3>& dims, const vol::ChannelGrid& exemplar) {
  TEXSIM_VERIFY(dims[0] <= slab.size() && dims[1] <= slab.size() && dims[2] <= slab.size(),
                "crop box larger than the synthesized level");
  std::vector<Coord> local;
  if (!slab.layout().replicated || comm.is_root())
    local = cropped_owned(slab, dims);
  const vol::Dims grid_dims{dims[0], dims[1], dims[2]};
  SynthesisResult result{comm.is_root() ? vol::ChannelGrid(grid_dims, exemplar.channels())
                                        : vol::ChannelGrid()};
  // Slabs are in z order by rank, so rank order is the volume's order; each slab is coloured as
  // it arrives and dropped, so rank 0 holds the colours and one slab, never every coordinate.
  std::size_t next = 0;
  par::stream_to_root(
      comm, std::as_bytes(std::span<const Coord>(local)),
      [&](int, std::span<const std::byte> bytes) {
        const std::size_t count = bytes.size() / sizeof(Coord);
        TEXSIM_VERIFY(next + count <= grid_dims.count(),
                      "more voxels than the " << grid_dims.count() << "-voxel result");
        for (std::size_t v = 0; v < count; ++v, ++next) {
          Coord c;
          std::memcpy(&c, bytes.data() + v * sizeof(Coord), sizeof(Coord));
          const auto colour = exemplar.voxel(exemplar.index(c.x, c.y, c.z));
          std::copy(colour.begin(), colour.end(), result.colours.voxel(next).begin());
        }
      });
  if (comm.is_root())
    TEXSIM_VERIFY(next == grid_dims.count(),
                  "gathered " << next << " voxels for a " << grid_dims.count() << "-voxel result");
  return result;
}

std::vector<std::filesystem::path> write_result(const std::filesystem::path& dir,
                                                const SynthesisResult& result,
                                                const std::vector<int>& cross_sections) {
  std::vector<std::filesystem::path> written;
  const auto vdb = dir / "solid_synthesis.vdb";
  vol::write_vdb(vdb, result.colours, result.colours.channels() == 1 ? "density" : "colour");
  written.push_back(vdb);
  for (const int p : cross_sections) {
    // One set per position: the combined image is named after the basename alone.
    const auto slices = vol::write_cross_sections(
        dir / "slices", "solid_synthesis_" + std::to_string(p), result.colours, {p, p, p});
    written.insert(written.end(), slices.begin(), slices.end());
  }
  return written;
}

std::vector<std::filesystem::path> write_parallel_result(const par::Comm& comm,
                                                         const std::filesystem::path& dir,
                                                         const CoordinateSlab& slab,
                                                         const std::array<int, 3>& dims,
                                                         const vol::ChannelGrid& exemplar) {
  // This rank's planes [z_first, z_last] of the cropped result: its slab and the next slab's
  // first plane (from the halo); a replicated level is written by rank 0 alone.
  const LevelLayout& layout = slab.layout();
  int z_first = 0, z_last = -1;
  if (!layout.replicated) {
    z_first = layout.z_begin;
    z_last = std::min(layout.z_end, dims[2] - 1);
  } else if (comm.is_root()) {
    z_last = dims[2] - 1;
  }
  std::optional<vol::RgbGrid> coordinates, colour;
  std::optional<vol::ScalarGrid> density;
  if (z_last >= z_first) {
    const vol::Dims piece{dims[0], dims[1], z_last - z_first + 1};
    coordinates.emplace(piece);
    if (exemplar.channels() == 1)
      density.emplace(piece);
    else
      colour.emplace(piece);
    for (int k = 0; k < piece.nz; ++k)
      for (int j = 0; j < piece.ny; ++j)
        for (int i = 0; i < piece.nx; ++i) {
          const Coord& c = slab.at(i, j, z_first + k);
          coordinates->at(i, j, k) = {static_cast<float>(c.x), static_cast<float>(c.y),
                                      static_cast<float>(c.z)};
          const auto value = exemplar.voxel(exemplar.index(c.x, c.y, c.z));
          if (density)
            density->at(i, j, k) = value[0];
          else
            colour->at(i, j, k) = {value[0], value[1], value[2]};
        }
  }
  const auto pointer = [](const auto& grid) { return grid ? &*grid : nullptr; };
  std::vector<std::filesystem::path> written;
  written.push_back(exemplar.channels() == 1
                        ? vol::write_parallel_vti(comm, dir, "solid_synthesis",
                                                  {pointer(density), z_first}, dims, "density")
                        : vol::write_parallel_vti(comm, dir, "solid_synthesis",
                                                  {pointer(colour), z_first}, dims, "colour"));
  written.push_back(vol::write_parallel_vti(comm, dir, "exemplar_coordinates",
                                            {pointer(coordinates), z_first}, dims,
                                            "exemplar_coordinate"));
  return written;
}

} // namespace texsim::pipelines::solid_synthesis
