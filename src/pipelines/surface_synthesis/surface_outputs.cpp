#include "pipelines/surface_synthesis/surface_outputs.hpp"

#include "geom/bump_map.hpp"
#include "geom/split_surface_sampler.hpp"
#include "geom/texture_atlas.hpp"
#include "img/colour_histogram.hpp"
#include "img/image_io.hpp"
#include "io/parallel_surface_writer.hpp"
#include "io/textured_obj_writer.hpp"
#include "par/collective.hpp"
#include "par/fetch_from_owners.hpp"

#include <mpi.h>

namespace texsim::pipelines::surface_synthesis {
namespace {

/// The finest level's colours at every vertex of M_s (rank 0's `surface`): linear on the retiled
/// triangle nearest to each vertex, found on the ranks' shares of the level (their corners'
/// colours fetched from the owners' runs). Empty on the other ranks. Collective.
std::vector<img::Rgb> colours_on_surface(const par::Comm& comm, const geom::TriangleMesh& surface,
                                         const RetiledLevel& finest, const LevelColours& colours) {
  const geom::LocalSurface& share = finest.triangles.owned_surface();
  const auto corner_colours = par::fetch_from_owners(comm, finest.rank_offsets, share.vertex_ids,
                                                     std::span<const img::Rgb>(colours.colours));
  std::vector<std::array<double, 3>> values;
  values.reserve(corner_colours.size());
  for (const auto& c : corner_colours)
    values.push_back({c.r, c.g, c.b});
  const auto sampled =
      geom::sample_split_surface(comm, share.mesh, share.triangle_ids, values,
                                 comm.rank == 0 ? std::span<const geom::Vec3>(surface.positions)
                                                : std::span<const geom::Vec3>());
  std::vector<img::Rgb> result;
  result.reserve(sampled.size());
  for (const auto& v : sampled)
    result.push_back({float(v[0]), float(v[1]), float(v[2])});
  return result;
}

std::vector<double> xyz_of(std::span<const geom::Vec3> positions) {
  std::vector<double> xyz;
  for (const auto& p : positions)
    xyz.insert(xyz.end(), {p.x(), p.y(), p.z()});
  return xyz;
}

/// The atlas image: every used texel interpolates the vertex colours of its triangle.
img::RgbImage fill_atlas(const geom::TriangleMesh& surface, const geom::TextureAtlas& atlas,
                         std::span<const img::Rgb> vertex_colours) {
  img::RgbImage image(atlas.resolution, atlas.resolution);
  for (const auto& texel : geom::atlas_texels(surface, atlas)) {
    const auto& t = surface.triangles[std::size_t(texel.triangle)];
    img::Rgb c;
    for (int ch = 0; ch < 3; ++ch) {
      double value = 0;
      for (std::size_t k = 0; k < 3; ++k)
        value += texel.weights[k] * vertex_colours[std::size_t(t[k])][ch];
      c[ch] = float(value);
    }
    image.at(texel.x, texel.y) = c;
  }
  return image;
}

} // namespace

SurfaceOutputs write_surface_outputs(const par::Comm& comm, const geom::TriangleMesh& surface,
                                     const RetiledLevel& finest, const LevelColours& colours,
                                     const img::RgbImage& exemplar,
                                     const SurfaceSynthesisSettings& settings,
                                     const std::filesystem::path& output_dir) {
  SurfaceOutputs outputs;
  // The finest level's colour histogram, each rank counting its run's (counts add up exactly).
  img::ColourHistogram level_histogram(3), exemplar_histogram(3);
  level_histogram.add(
      {reinterpret_cast<const float*>(colours.colours.data()), 3 * colours.colours.size()});
  MPI_Allreduce(MPI_IN_PLACE, level_histogram.counts().data(), int(level_histogram.counts().size()),
                MPI_INT64_T, MPI_SUM, comm.raw);
  exemplar_histogram.add(
      {reinterpret_cast<const float*>(exemplar.data().data()), 3 * exemplar.size()});
  outputs.histogram_distance = img::histogram_distance(level_histogram, exemplar_histogram);

  const std::vector<img::Rgb> on_surface = colours_on_surface(comm, surface, finest, colours);
  std::vector<double> xyz, colour_values, height;
  std::vector<std::int64_t> triangles;
  if (comm.rank == 0) {
    xyz = xyz_of(surface.positions);
    for (const auto& c : on_surface) {
      colour_values.insert(colour_values.end(), {c.r, c.g, c.b});
      height.push_back(0.2126 * c.r + 0.7152 * c.g + 0.0722 * c.b); // Rec. 709 luminance
    }
    for (const auto& t : surface.triangles)
      triangles.insert(triangles.end(), {t[0], t[1], t[2]});
  }
  io::SurfacePiece piece{xyz, triangles, {}, {}};
  piece.point_fields = {{"color", 3, std::span<const double>(colour_values)},
                        {"luminance", 1, std::span<const double>(height)}};
  outputs.files.push_back(
      io::write_parallel_surface(comm, output_dir, "surface", piece, io::SurfaceFormat::vtp));

  if (settings.displacement_scale > 0) {
    std::vector<double> displaced_xyz, normals;
    if (comm.rank == 0) {
      const auto bumped = geom::bump_map(surface, height, settings.displacement_scale);
      displaced_xyz = xyz_of(bumped.positions);
      normals = xyz_of(bumped.normals);
    }
    io::SurfacePiece displaced{displaced_xyz, triangles, {}, {}};
    displaced.point_fields = {{"color", 3, std::span<const double>(colour_values)},
                              {"height", 1, std::span<const double>(height)},
                              {"Normals", 3, std::span<const double>(normals)}};
    outputs.files.push_back(io::write_parallel_surface(comm, output_dir, "displaced", displaced,
                                                       io::SurfaceFormat::vtp));
  }

  if (settings.atlas.resolution > 0) {
    par::run_collectively(comm, [&] {
      if (comm.rank != 0)
        return;
      geom::AtlasSettings atlas_settings;
      atlas_settings.resolution = settings.atlas.resolution;
      atlas_settings.gutter = settings.atlas.gutter;
      const auto atlas = geom::build_texture_atlas(surface, atlas_settings);
      img::write_png(output_dir / "atlas.png", fill_atlas(surface, atlas, on_surface));
      std::vector<std::int32_t> corners;
      std::vector<double> uv;
      for (std::size_t t = 0; t < surface.triangles.size(); ++t) {
        corners.insert(corners.end(), surface.triangles[t].begin(), surface.triangles[t].end());
        for (const auto& c : atlas.corner_uv[t])
          uv.insert(uv.end(), {c.x(), c.y()});
      }
      io::write_textured_obj(output_dir / "textured.obj", {xyz, corners, uv, {}});
    });
    outputs.files.push_back(output_dir / "atlas.png");
    outputs.files.push_back(output_dir / "textured.obj");
  }
  return outputs;
}

} // namespace texsim::pipelines::surface_synthesis
