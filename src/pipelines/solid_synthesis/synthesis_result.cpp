#include "pipelines/solid_synthesis/synthesis_result.hpp"

#include "core/error.hpp"
#include "par/gather_to_root.hpp"
#include "vol/cross_section_writer.hpp"
#include "vol/vdb_io.hpp"
#include "vol/vti_io.hpp"

#include <algorithm>
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
  // Slabs are in z order by rank, so rank order is the volume's order; any size per rank.
  const std::vector<Coord> all = par::gather_to_root(comm, std::span<const Coord>(local));
  if (!comm.is_root())
    return {};
  const vol::Dims grid_dims{dims[0], dims[1], dims[2]};
  TEXSIM_VERIFY(all.size() == grid_dims.count(), "gathered " << all.size() << " voxels for a "
                                                             << grid_dims.count()
                                                             << "-voxel result");

  SynthesisResult result{vol::ChannelGrid(grid_dims, 3),
                         vol::ChannelGrid(grid_dims, exemplar.channels())};
  for (std::size_t v = 0; v < all.size(); ++v) {
    const Coord& c = all[v];
    auto coordinate = result.coordinates.voxel(v);
    coordinate[0] = static_cast<float>(c.x);
    coordinate[1] = static_cast<float>(c.y);
    coordinate[2] = static_cast<float>(c.z);
    const auto colour = exemplar.voxel(exemplar.index(c.x, c.y, c.z));
    std::copy(colour.begin(), colour.end(), result.colours.voxel(v).begin());
  }
  return result;
}

std::vector<std::filesystem::path> write_result(const std::filesystem::path& dir,
                                                const SynthesisResult& result,
                                                const std::vector<int>& cross_sections) {
  std::vector<std::filesystem::path> written;
  const auto vdb = dir / "solid_synthesis.vdb";
  const auto vti = dir / "solid_synthesis.vti";
  if (result.colours.channels() == 1) {
    vol::ScalarGrid density(result.colours.dims());
    std::copy(result.colours.data().begin(), result.colours.data().end(), density.data().begin());
    vol::write_vdb(vdb, density, "density");
    vol::write_vti(vti, density, "density");
  } else {
    const vol::RgbGrid colour = vol::to_rgb(result.colours);
    vol::write_vdb(vdb, colour, "colour");
    vol::write_vti(vti, colour, "colour");
  }
  const auto coordinates = dir / "exemplar_coordinates.vti";
  vol::write_vti(coordinates, vol::to_rgb(result.coordinates), "exemplar_coordinate");
  written.insert(written.end(), {vdb, vti, coordinates});
  for (const int p : cross_sections) {
    // One set per position: the combined image is named after the basename alone.
    const auto slices = vol::write_cross_sections(
        dir / "slices", "solid_synthesis_" + std::to_string(p), result.colours, {p, p, p});
    written.insert(written.end(), slices.begin(), slices.end());
  }
  return written;
}

} // namespace texsim::pipelines::solid_synthesis
