#include "pipelines/solid_synthesis/synthesis_result.hpp"

#include "core/error.hpp"
#include "par/collective.hpp"
#include "par/gather_to_root.hpp"
#include "pipelines/solid_synthesis/slab_colours.hpp"
#include "vol/cross_section_writer.hpp"
#include "vol/parallel_vti_writer.hpp"
#include "vol/vdb_io.hpp"

#include <algorithm>
#include <cstring>
#include <optional>
#include <string>

namespace texsim::pipelines::solid_synthesis {
namespace {

/// S's voxels on planes [begin, end) of the slab inside the crop box, plane by plane, x fastest.
std::vector<Coord> cropped_planes(const CoordinateSlab& slab, const std::array<int, 3>& dims,
                                  PlaneRange planes) {
  std::vector<Coord> out;
  out.reserve(std::size_t(std::max(0, planes.end - planes.begin)) * std::size_t(dims[0]) *
              std::size_t(dims[1]));
  for (int k = planes.begin; k < planes.end; ++k)
    for (int j = 0; j < dims[1]; ++j)
      for (int i = 0; i < dims[0]; ++i)
        out.push_back(slab.voxel(i, j, k));
  return out;
}

} // namespace

std::vector<std::filesystem::path>
write_assembled_result(const par::Comm& comm, const std::filesystem::path& dir,
                       const CoordinateSlab& slab, const std::array<int, 3>& dims,
                       const vol::ChannelGrid& exemplar, const std::vector<int>& cross_sections) {
  TEXSIM_VERIFY(dims[0] <= slab.size() && dims[1] <= slab.size() && dims[2] <= slab.size(),
                "crop box larger than the synthesized level");
  const PlaneRange planes = reported_planes(comm, slab, dims[2]);
  // Rank 0 reads its own planes from the slab; the others send theirs.
  const std::vector<Coord> mine =
      comm.is_root() ? std::vector<Coord>() : cropped_planes(slab, dims, planes);

  const vol::Dims grid{dims[0], dims[1], dims[2]};
  const int channels = exemplar.channels();
  std::optional<vol::VdbPlaneWriter> vdb;
  std::vector<vol::CrossSections> sections;
  if (comm.is_root()) {
    vdb.emplace(grid, channels, channels == 1 ? "density" : "colour");
    for (const int p : cross_sections)
      sections.emplace_back(grid, channels, std::array<int, 3>{p, p, p});
    // The comparison's result row: through the centres, like the exemplar's.
    sections.emplace_back(grid, channels,
                          std::array<int, 3>{dims[0] / 2, dims[1] / 2, dims[2] / 2});
  }
  // Slabs are in z order by rank, so rank order is the volume's order; each plane is coloured as
  // it arrives and dropped.
  const std::size_t plane_voxels = std::size_t(dims[0]) * std::size_t(dims[1]);
  int next_plane = 0;
  const auto add_plane = [&](std::span<const float> colours) {
    vdb->add_planes(colours);
    for (vol::CrossSections& s : sections)
      s.add_planes(next_plane, colours);
    ++next_plane;
  };
  par::stream_to_root(
      comm, std::as_bytes(std::span<const Coord>(mine)),
      [&](int rank, std::span<const std::byte> bytes) {
        if (rank == comm.rank) {
          for (int k = planes.begin; k < planes.end; ++k)
            add_plane(coloured_planes(slab, exemplar, dims[0], dims[1], k, 1).data());
          return;
        }
        TEXSIM_VERIFY(bytes.size() % (plane_voxels * sizeof(Coord)) == 0,
                      "rank " << rank << " sent " << bytes.size() << " bytes, not whole planes");
        std::vector<float> plane(plane_voxels * std::size_t(channels));
        for (std::size_t at = 0; at < bytes.size(); at += plane_voxels * sizeof(Coord)) {
          for (std::size_t v = 0; v < plane_voxels; ++v) {
            Coord c;
            std::memcpy(&c, bytes.data() + at + v * sizeof(Coord), sizeof(Coord));
            const auto colour = colour_at(exemplar, c);
            std::copy(colour.begin(), colour.end(), plane.begin() + std::ptrdiff_t(v * channels));
          }
          add_plane(plane);
        }
      });
  std::vector<std::filesystem::path> written;
  // A file that cannot be written fails every rank, not rank 0 alone.
  par::run_collectively(comm, [&] {
    if (!comm.is_root())
      return;
    TEXSIM_VERIFY(next_plane == dims[2],
                  "assembled " << next_plane << " planes of a " << dims[2] << "-plane result");
    written.push_back(dir / "solid_synthesis.vdb");
    vdb->write(written.back());
    for (std::size_t s = 0; s + 1 < sections.size(); ++s) {
      // One set per position: the combined image is named after the basename alone.
      const auto slices = vol::write_cross_sections(
          dir / "slices", "solid_synthesis_" + std::to_string(cross_sections[s]), sections[s]);
      written.insert(written.end(), slices.begin(), slices.end());
    }
    written.push_back(
        vol::write_comparison(dir / "slices" / "comparison.png", exemplar, sections.back()));
  });
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
  const bool has_piece = z_last >= z_first;
  const vol::Dims piece{dims[0], dims[1], has_piece ? z_last - z_first + 1 : 1};
  // One volume at a time: each piece grid is as large as the slab.
  const auto filled = [&](auto grid, const auto& value_of) {
    for (int k = 0; k < piece.nz; ++k)
      for (int j = 0; j < piece.ny; ++j)
        for (int i = 0; i < piece.nx; ++i)
          grid.at(i, j, k) = value_of(slab.voxel(i, j, z_first + k));
    return grid;
  };
  std::vector<std::filesystem::path> written;
  if (exemplar.channels() == 1) {
    std::optional<vol::ScalarGrid> density;
    if (has_piece)
      density =
          filled(vol::ScalarGrid(piece), [&](const Coord& c) { return colour_at(exemplar, c)[0]; });
    written.push_back(vol::write_parallel_vti(
        comm, dir, "solid_synthesis", {density ? &*density : nullptr, z_first}, dims, "density"));
  } else {
    std::optional<vol::RgbGrid> colour;
    if (has_piece)
      colour = filled(vol::RgbGrid(piece), [&](const Coord& c) {
        const auto v = colour_at(exemplar, c);
        return img::Rgb{v[0], v[1], v[2]};
      });
    written.push_back(vol::write_parallel_vti(
        comm, dir, "solid_synthesis", {colour ? &*colour : nullptr, z_first}, dims, "colour"));
  }
  std::optional<vol::RgbGrid> coordinates;
  if (has_piece)
    coordinates = filled(vol::RgbGrid(piece), [](const Coord& c) {
      return img::Rgb{static_cast<float>(c.x), static_cast<float>(c.y), static_cast<float>(c.z)};
    });
  written.push_back(vol::write_parallel_vti(comm, dir, "exemplar_coordinates",
                                            {coordinates ? &*coordinates : nullptr, z_first}, dims,
                                            "exemplar_coordinate"));
  return written;
}

} // namespace texsim::pipelines::solid_synthesis
