#include "pipelines/solid_synthesis/synthesis_result.hpp"

#include "core/error.hpp"
#include "par/collective.hpp"
#include "pipelines/solid_synthesis/slab_colours.hpp"
#include "vol/cross_section_writer.hpp"
#include "vol/parallel_vdb_writer.hpp"
#include "vol/parallel_vti_writer.hpp"

#include <mpi.h>

#include <algorithm>
#include <optional>
#include <string>

namespace texsim::pipelines::solid_synthesis {
namespace {

/// The cross sections a run writes: one set per position in `cross_sections`, then the
/// comparison's row through the centres (like the exemplar's).
std::vector<vol::CrossSections> empty_sections(const vol::Dims& grid, int channels,
                                               const std::vector<int>& cross_sections) {
  std::vector<vol::CrossSections> sections;
  for (const int p : cross_sections)
    sections.emplace_back(grid, channels, std::array<int, 3>{p, p, p});
  sections.emplace_back(grid, channels, std::array<int, 3>{grid.nx / 2, grid.ny / 2, grid.nz / 2});
  return sections;
}

/// The rank that writes section set s: spread over the ranks after rank 0, which writes the
/// .vdb's header and structure.
int section_writer(const par::Comm& comm, std::size_t s) {
  return comm.size == 1 ? 0 : 1 + static_cast<int>(s % std::size_t(comm.size - 1));
}

} // namespace

std::vector<std::filesystem::path>
write_volume_and_sections(const par::Comm& comm, const std::filesystem::path& dir,
                          const CoordinateSlab& slab, const std::array<int, 3>& dims,
                          const vol::ChannelGrid& exemplar, const std::vector<int>& cross_sections,
                          vol::VdbCompression compression, StageTimers& timers) {
  TEXSIM_VERIFY(dims[0] <= slab.size() && dims[1] <= slab.size() && dims[2] <= slab.size(),
                "crop box larger than the synthesized level");
  const PlaneRange planes = reported_planes(comm, slab, dims[2]);
  const vol::Dims grid{dims[0], dims[1], dims[2]};
  const int channels = exemplar.channels();

  // Every rank colours its own planes, keeps them for the .vdb and takes their share of every
  // cross section.
  std::vector<vol::CrossSections> sections = empty_sections(grid, channels, cross_sections);
  // Room for the 7 planes the .vdb writer may append to finish a leaf layer.
  std::vector<float> colours;
  colours.reserve(std::size_t(std::max(planes.end - planes.begin, 0) + 7) * std::size_t(dims[0]) *
                  std::size_t(dims[1]) * std::size_t(channels));
  for (int k = planes.begin; k < planes.end; ++k) {
    auto stage = timers.scope("colouring");
    const vol::ChannelGrid plane = coloured_planes(slab, exemplar, dims[0], dims[1], k, 1);
    for (vol::CrossSections& s : sections)
      s.add_planes(k, plane.data());
    colours.insert(colours.end(), plane.data().begin(), plane.data().end());
  }
  {
    // Every rank writes the leaves of its planes into the one .vdb (the file's bytes do not
    // depend on the rank count).
    auto stage = timers.scope("vdb");
    vol::write_parallel_vdb(comm, dir / "solid_synthesis.vdb", grid, channels, planes.begin,
                            std::move(colours), channels == 1 ? "density" : "colour", compression);
  }
  {
    // Each pixel comes from the one rank that owns its plane and is 0 elsewhere: the sum is
    // exact, whatever order MPI adds in.
    auto stage = timers.scope("slices");
    for (std::size_t s = 0; s < sections.size(); ++s) {
      const int writer = section_writer(comm, s);
      for (int axis = 0; axis < 3; ++axis) {
        std::span<img::Rgb> pixels = sections[s].picture(axis).data();
        static_assert(sizeof(img::Rgb) == 3 * sizeof(float));
        const int count = static_cast<int>(pixels.size() * 3);
        MPI_Reduce(comm.rank == writer ? MPI_IN_PLACE : pixels.data(), pixels.data(), count,
                   MPI_FLOAT, MPI_SUM, writer, comm.raw);
      }
    }
    // A file that cannot be written fails every rank, not its writer alone.
    par::run_collectively(comm, [&] {
      for (std::size_t s = 0; s < sections.size(); ++s) {
        if (section_writer(comm, s) != comm.rank)
          continue;
        if (s + 1 < sections.size()) // one set per position, named after it
          vol::write_cross_sections(
              dir / "slices", "solid_synthesis_" + std::to_string(cross_sections[s]), sections[s]);
        else
          vol::write_comparison(dir / "slices" / "comparison.png", exemplar, sections[s]);
      }
    });
  }
  std::vector<std::filesystem::path> written;
  if (comm.is_root()) {
    written.push_back(dir / "solid_synthesis.vdb");
    for (const int p : cross_sections) {
      const auto paths = vol::cross_section_paths(
          dir / "slices", "solid_synthesis_" + std::to_string(p), {p, p, p});
      written.insert(written.end(), paths.begin(), paths.end());
    }
    written.push_back(dir / "slices" / "comparison.png");
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
