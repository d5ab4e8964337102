#include "pipelines/fluid_lapped/frame_outputs.hpp"

#include "core/error.hpp"
#include "geom/seam_split.hpp"
#include "geom/texture_atlas.hpp"
#include "img/image_io.hpp"
#include "io/image_data_writer.hpp"
#include "io/parallel_surface_writer.hpp"
#include "par/collective.hpp"

#include <mpi.h>

#include <algorithm>
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
      ids_(open_series(comm, dir_ / "patch_ids.pvd", restart_time)) {}

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

void FrameOutputs::write_atlas(int k, double time, const AtlasCompositor& compositor,
                               std::span<const Patch> patches) {
  const int root = k % comm_.size;
  const auto samples = compositor.gather(root);
  // The birth frame of every patch, for the ages.
  struct Birth {
    std::int64_t id;
    std::int32_t frame;
  };
  std::vector<Birth> mine;
  for (const auto& patch : patches)
    mine.push_back({patch.id, patch.birth_frame});
  const int bytes = int(mine.size() * sizeof(Birth));
  std::vector<int> counts(std::size_t(comm_.size)), offsets(std::size_t(comm_.size));
  MPI_Gather(&bytes, 1, MPI_INT, counts.data(), 1, MPI_INT, root, comm_.raw);
  for (int r = 1; r < comm_.size; ++r)
    offsets[std::size_t(r)] = offsets[std::size_t(r) - 1] + counts[std::size_t(r) - 1];
  std::vector<Birth> births(
      comm_.rank == root ? std::size_t(offsets.back() + counts.back()) / sizeof(Birth) : 0);
  MPI_Gatherv(mine.data(), bytes, MPI_BYTE, births.data(), counts.data(), offsets.data(), MPI_BYTE,
              root, comm_.raw);
  const std::string png = "atlas/" + numbered("atlas", k, ".png");
  const std::string displacement = "displacement/" + numbered("displacement", k, ".png");
  const std::string ids = "patch_ids/" + numbered("patch_ids", k, ".vti");
  par::run_collectively(comm_, [&] {
    if (comm_.rank != root)
      return;
    std::sort(births.begin(), births.end(),
              [](const Birth& a, const Birth& b) { return a.id < b.id; });
    const int n = compositor.resolution();
    img::RgbImage colour(n, n);
    std::vector<std::uint16_t> heights;
    if (exemplar_.displacement)
      heights.assign(std::size_t(n) * std::size_t(n), 0);
    std::vector<std::int64_t> id(samples.size());
    std::vector<std::int32_t> age(samples.size(), -1);
    std::vector<float> uv(2 * samples.size(), 0.0f); // the samples' own floats
    auto birth = births.end();
    for (std::size_t i = 0; i < samples.size(); ++i) {
      const auto& s = samples[i];
      id[i] = s.patch;
      if (s.patch < 0)
        continue;
      const auto texel = erosion_.exemplar_texel(Eigen::Vector2d(s.u, s.v));
      const int x = int(i % std::size_t(n)), y = int(i / std::size_t(n));
      colour.at(x, y) = exemplar_.colour.at(texel[0], texel[1]);
      if (exemplar_.displacement)
        heights[i] = std::uint16_t(std::lround(
            65535.0 * std::clamp(exemplar_.displacement->at(texel[0], texel[1]), 0.0f, 1.0f)));
      // Neighbouring texels mostly show the same patch: search only when it changes.
      if (birth == births.end() || birth->id != s.patch) {
        birth = std::lower_bound(births.begin(), births.end(), s.patch,
                                 [](const Birth& b, std::int64_t wanted) { return b.id < wanted; });
        TEXSIM_VERIFY(birth != births.end() && birth->id == s.patch,
                      "texel of patch " << s.patch << " that no rank holds");
      }
      age[i] = k - birth->frame;
      uv[2 * i] = s.u;
      uv[2 * i + 1] = s.v;
    }
    std::filesystem::create_directories(dir_ / "atlas");
    img::write_png(dir_ / png, colour);
    if (exemplar_.displacement) {
      std::filesystem::create_directories(dir_ / "displacement");
      img::write_png16(dir_ / displacement, heights, n, n);
    }
    std::filesystem::create_directories(dir_ / "patch_ids");
    io::write_image_data(dir_ / ids, n, n,
                         {{"patch_id", 1, std::span<const std::int64_t>(id)},
                          {"age", 1, std::span<const std::int32_t>(age)},
                          {"uv", 2, std::span<const float>(uv)}});
  });
  ids_.add(time, ids);
}

} // namespace texsim::pipelines::fluid_lapped
