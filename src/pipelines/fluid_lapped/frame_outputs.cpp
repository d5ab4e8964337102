#include "pipelines/fluid_lapped/frame_outputs.hpp"

#include "core/error.hpp"
#include "geom/seam_split.hpp"
#include "geom/texture_atlas.hpp"
#include "img/image_io.hpp"
#include "io/parallel_image_data_writer.hpp"
#include "io/parallel_png_writer.hpp"
#include "io/parallel_surface_writer.hpp"
#include "par/collective.hpp"
#include "par/record_exchange.hpp"

#include <mpi.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>

namespace texsim::pipelines::fluid_lapped {
namespace {

std::string numbered(const std::string& stem, int k, const std::string& extension) {
  char name[64];
  std::snprintf(name, sizeof name, "%s_%04d%s", stem.c_str(), k, extension.c_str());
  return name;
}

io::PvdSeries open_series(const par::Comm& comm, const std::filesystem::path& path,
                          std::optional<double> restart_time) {
  return restart_time ? io::PvdSeries::resume(comm, path, *restart_time)
                      : io::PvdSeries(comm, path);
}

/// The piece of a mesh this rank writes: triangles [first, last) of an even split, with the
/// vertices they use (in order of first use) and each one's index in the mesh.
struct MeshPiece {
  std::vector<double> xyz;
  std::vector<std::int64_t> triangles;
  std::vector<std::int32_t> vertices;
};

MeshPiece piece_of(const par::Comm& comm, const geom::TriangleMesh& mesh) {
  const auto n = std::size_t(mesh.num_triangles());
  const auto first = n * std::size_t(comm.rank) / std::size_t(comm.size);
  const auto last = n * std::size_t(comm.rank + 1) / std::size_t(comm.size);
  MeshPiece piece;
  std::map<std::int32_t, std::int64_t> local;
  for (std::size_t t = first; t < last; ++t)
    for (const auto v : mesh.triangles[t]) {
      const auto [at, added] = local.emplace(v, std::int64_t(piece.vertices.size()));
      if (added) {
        piece.vertices.push_back(v);
        const auto& p = mesh.positions[std::size_t(v)];
        piece.xyz.insert(piece.xyz.end(), {p.x(), p.y(), p.z()});
      }
      piece.triangles.push_back(at->second);
    }
  return piece;
}

} // namespace

FrameOutputs::FrameOutputs(const par::Comm& comm, std::filesystem::path output_dir,
                           const FluidExemplar& exemplar, const ErosionMask& erosion,
                           std::optional<double> restart_time)
    : comm_(comm), dir_(std::move(output_dir)), exemplar_(exemplar), erosion_(erosion),
      surface_(open_series(comm, dir_ / "surface.pvd", restart_time)),
      patches_(open_series(comm, dir_ / "patches.pvd", restart_time)),
      ids_(open_series(comm, dir_ / "patch_ids.pvd", restart_time)) {
  // The exemplar's texels as the PNGs store them, converted once.
  for (const auto& c : exemplar_.colour.data())
    exemplar_rgb8_.insert(
        exemplar_rgb8_.end(),
        {img::channel_to_byte(c.r), img::channel_to_byte(c.g), img::channel_to_byte(c.b)});
  if (exemplar_.displacement)
    for (const float h : exemplar_.displacement->data()) {
      const auto level = std::uint16_t(std::lround(65535.0 * std::clamp(h, 0.0f, 1.0f)));
      exemplar_height16_.insert(exemplar_height16_.end(),
                                {std::uint8_t(level >> 8), std::uint8_t(level & 0xff)});
    }
}

std::vector<std::filesystem::path> FrameOutputs::series() const {
  return {surface_.path(), patches_.path(), ids_.path()};
}

void FrameOutputs::write(int k, double time, const PreparedFrame& frame,
                         const AtlasCompositor& compositor, std::span<const Patch> patches,
                         const VelocityField* velocity) {
  write_surface(k, time, frame, velocity);
  write_patches(k, time, patches);
  write_atlas(k, time, compositor, patches);
}

void FrameOutputs::write_surface(int k, double time, const PreparedFrame& frame,
                                 const VelocityField* velocity) {
  const auto split = geom::split_at_seams(frame.frame.mesh, frame.atlas.corner_uv);
  const auto piece = piece_of(comm_, split.mesh);
  std::vector<double> uv, velocities;
  for (const auto v : piece.vertices) {
    const auto& t = split.uv[std::size_t(v)];
    uv.insert(uv.end(), {t.x(), t.y()});
    const auto original = std::size_t(split.original_vertex[std::size_t(v)]);
    const geom::Vec3 u = !frame.frame.vertex_velocity.empty()
                             ? frame.frame.vertex_velocity[original]
                         : velocity ? velocity->at(frame.frame.mesh.positions[original], time)
                                    : geom::Vec3::Zero();
    velocities.insert(velocities.end(), {u.x(), u.y(), u.z()});
  }
  io::SurfacePiece out{piece.xyz, piece.triangles, {}, {}};
  out.point_fields.push_back({"uv", 2, std::span<const double>(uv)});
  out.point_fields.push_back({"velocity", 3, std::span<const double>(velocities)});
  out.texture_coordinates = "uv";
  const auto name = numbered("surface", k, "");
  io::write_parallel_surface(comm_, dir_ / "surface", name, out, io::SurfaceFormat::vtp);
  surface_.add(time, "surface/" + name + ".pvtp");
}

void FrameOutputs::write_patches(int k, double time, std::span<const Patch> patches) {
  std::vector<double> xyz, weights, uv;
  std::vector<std::int64_t> triangles, vertex_ids, triangle_ids;
  for (const auto& patch : patches) {
    const auto base = std::int64_t(xyz.size() / 3);
    for (std::size_t v = 0; v < patch.positions.size(); ++v) {
      const auto& p = patch.positions[v];
      xyz.insert(xyz.end(), {p.x(), p.y(), p.z()});
      uv.insert(uv.end(), {patch.rest_uv[v].x(), patch.rest_uv[v].y()});
      weights.push_back(patch.weights[v]);
      vertex_ids.push_back(patch.id);
    }
    for (const auto& t : patch.triangles) {
      triangles.insert(triangles.end(), {base + t[0], base + t[1], base + t[2]});
      triangle_ids.push_back(patch.id);
    }
  }
  io::SurfacePiece out{xyz, triangles, {}, {}};
  out.point_fields.push_back({"patch_id", 1, std::span<const std::int64_t>(vertex_ids)});
  out.point_fields.push_back({"w", 1, std::span<const double>(weights)});
  out.point_fields.push_back({"rest_uv", 2, std::span<const double>(uv)});
  out.cell_fields.push_back({"patch_id", 1, std::span<const std::int64_t>(triangle_ids)});
  const auto name = numbered("patches", k, "");
  io::write_parallel_surface(comm_, dir_ / "patches", name, out, io::SurfaceFormat::vtp);
  patches_.add(time, "patches/" + name + ".pvtp");
}

std::vector<FrameOutputs::Birth> FrameOutputs::births(std::span<const Patch> patches) const {
  std::vector<Birth> mine;
  for (const auto& patch : patches)
    mine.push_back({patch.id, patch.birth_frame});
  auto all = par::allgather_records(comm_, mine);
  std::sort(all.begin(), all.end(), [](const Birth& a, const Birth& b) { return a.id < b.id; });
  return all;
}

void FrameOutputs::write_atlas(int k, double time, const AtlasCompositor& compositor,
                               std::span<const Patch> patches) {
  // Strips of tile rows, an even share of them per rank in rank order: the same strips (and so
  // the same files) at any rank count.
  const int n = compositor.resolution(), strip_rows = compositor.tile_size();
  const int strips = (n + strip_rows - 1) / strip_rows;
  const int first_strip = int(std::int64_t(strips) * comm_.rank / comm_.size);
  const int end_strip = int(std::int64_t(strips) * (comm_.rank + 1) / comm_.size);
  const int first_row = std::min(first_strip * strip_rows, n);
  const int end_row = std::min(end_strip * strip_rows, n);
  // Also the row above (PNG's filters look at it) and the row below (the .vti pieces share it).
  const int fetched_first = end_row > first_row ? std::max(first_row - 1, 0) : 0;
  const int fetched_end = end_row > first_row ? std::min(end_row + 1, n) : 0;
  const auto samples = compositor.rows(fetched_first, fetched_end);
  const auto birth = births(patches);

  const auto texels = samples.size();
  std::vector<std::uint8_t> colour(3 * texels, 0), heights;
  if (exemplar_.displacement)
    heights.assign(2 * texels, 0);
  std::vector<std::int64_t> id(texels);
  std::vector<std::int32_t> age(texels, -1);
  std::vector<float> uv(2 * texels, 0.0f); // the samples' own floats
  // A texel of a patch no rank holds would be a bug: raised on every rank, so none waits.
  par::run_collectively(comm_, [&] {
    auto born = birth.end();
    for (std::size_t i = 0; i < texels; ++i) {
      const auto& s = samples[i];
      id[i] = s.patch;
      if (s.patch < 0)
        continue;
      const auto texel = erosion_.exemplar_texel(Eigen::Vector2d(s.u, s.v));
      const auto at =
          std::size_t(texel[1]) * std::size_t(exemplar_.colour.width()) + std::size_t(texel[0]);
      std::copy_n(&exemplar_rgb8_[3 * at], 3, &colour[3 * i]);
      if (exemplar_.displacement)
        std::copy_n(&exemplar_height16_[2 * at], 2, &heights[2 * i]);
      // Neighbouring texels mostly show the same patch: search only when it changes.
      if (born == birth.end() || born->id != s.patch) {
        born = std::lower_bound(birth.begin(), birth.end(), s.patch,
                                [](const Birth& b, std::int64_t wanted) { return b.id < wanted; });
        TEXSIM_VERIFY(born != birth.end() && born->id == s.patch,
                      "texel of patch " << s.patch << " that no rank holds");
      }
      age[i] = k - born->frame;
      uv[2 * i] = s.u;
      uv[2 * i + 1] = s.v;
    }
  });

  const int root = k % comm_.size;
  const auto own = std::size_t(first_row - fetched_first) * std::size_t(n); // first owned texel
  const auto png_rows = [&](const std::vector<std::uint8_t>& pixels, std::size_t bytes_per_texel) {
    const auto row_bytes = bytes_per_texel * std::size_t(n);
    const auto owned = std::span(pixels).subspan(own * bytes_per_texel,
                                                 std::size_t(end_row - first_row) * row_bytes);
    const auto above = first_row > 0 && end_row > first_row ? std::span(pixels).first(row_bytes)
                                                            : std::span<const std::uint8_t>();
    return io::PngRows{first_row, end_row - first_row, owned, above};
  };
  io::write_parallel_png(comm_, dir_ / "atlas" / numbered("atlas", k, ".png"), n, n,
                         io::PngPixels::rgb8, png_rows(colour, 3), strip_rows, root);
  if (exemplar_.displacement)
    io::write_parallel_png(comm_, dir_ / "displacement" / numbered("displacement", k, ".png"), n, n,
                           io::PngPixels::grey16, png_rows(heights, 2), strip_rows, root);
  const auto piece_texels = texels - own;
  const auto name = numbered("patch_ids", k, "");
  io::write_parallel_image_data(
      comm_, dir_ / "patch_ids", name, n, n, strip_rows,
      {first_strip,
       end_strip - first_strip,
       {{"patch_id", 1, std::span<const std::int64_t>(id).subspan(own, piece_texels)},
        {"age", 1, std::span<const std::int32_t>(age).subspan(own, piece_texels)},
        {"uv", 2, std::span<const float>(uv).subspan(2 * own, 2 * piece_texels)}}});
  ids_.add(time, "patch_ids/" + name + ".pvti");
}

} // namespace texsim::pipelines::fluid_lapped
