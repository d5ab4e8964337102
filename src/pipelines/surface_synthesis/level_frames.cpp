#include "pipelines/surface_synthesis/level_frames.hpp"

#include "core/log.hpp"
#include "io/parallel_surface_writer.hpp"
#include "par/fetch_from_owners.hpp"
#include "par/id_runs.hpp"

#include <algorithm>
#include <iterator>

namespace texsim::pipelines::surface_synthesis {
namespace {

constexpr const char* kSeries = "surface_synthesis.pvd";

io::PvdSeries open_series(const par::Comm& comm, const std::filesystem::path& dir,
                          std::optional<double> restart_time) {
  return restart_time ? io::PvdSeries::resume(comm, dir / kSeries, *restart_time)
                      : io::PvdSeries(comm, dir / kSeries);
}

} // namespace

LevelFrames::LevelFrames(const par::Comm& comm, const std::filesystem::path& output_dir,
                         std::optional<double> restart_time)
    : comm_(comm), output_dir_(output_dir), series_(open_series(comm, output_dir, restart_time)) {}

void LevelFrames::write(int levels, int level, Pass pass, const RetiledLevel& retiled,
                        std::span<const geom::Vec3> directions, const LevelColours& colours) {
  // Each rank writes the triangles whose smallest corner is in its run, from its run's star.
  const std::int64_t first = retiled.run_begin(comm_.rank);
  const std::int64_t end = retiled.run_begin(comm_.rank + 1);
  const geom::LocalSurface& star = retiled.star;
  const auto global = [&](std::int32_t local) { return star.vertex_ids[std::size_t(local)]; };
  std::vector<char> kept(star.mesh.triangles.size(), 0), corner(star.vertex_ids.size(), 0);
  for (std::size_t t = 0; t < kept.size(); ++t) {
    const auto& c = star.mesh.triangles[t];
    // Local ids follow the level's, so the smallest local corner is the smallest on the level.
    const std::int64_t smallest = global(std::min({c[0], c[1], c[2]}));
    kept[t] = smallest >= first && smallest < end;
    if (kept[t])
      for (const auto v : c)
        corner[std::size_t(v)] = 1;
  }
  std::vector<std::int32_t> used; // star-local, so in increasing order of the level's ids
  std::vector<std::int32_t> local_of(corner.size(), -1);
  for (std::size_t v = 0; v < corner.size(); ++v)
    if (corner[v]) {
      local_of[v] = std::int32_t(used.size());
      used.push_back(std::int32_t(v));
    }
  std::vector<std::int64_t> triangles;
  for (std::size_t t = 0; t < kept.size(); ++t)
    if (kept[t])
      for (const auto v : star.mesh.triangles[t])
        triangles.push_back(local_of[std::size_t(v)]);

  // The corners' directions and colours, from their owners.
  struct CornerValues {
    double s[3];
    img::Rgb colour;
  };
  std::vector<CornerValues> run_values;
  for (std::size_t i = 0; i < directions.size(); ++i)
    run_values.push_back(
        {{directions[i].x(), directions[i].y(), directions[i].z()}, colours.colours[i]});
  std::vector<std::int64_t> ids;
  for (const std::int32_t v : used)
    ids.push_back(global(v));
  const auto used_values = par::fetch_from_owners(comm_, retiled.rank_offsets, std::span(ids),
                                                  std::span<const CornerValues>(run_values));
  std::vector<double> xyz, colour, s;
  std::vector<std::int32_t> owner;
  for (std::size_t i = 0; i < used.size(); ++i) {
    const auto& p = star.mesh.positions[std::size_t(used[i])];
    xyz.insert(xyz.end(), {p.x(), p.y(), p.z()});
    const auto& c = used_values[i].colour;
    colour.insert(colour.end(), {c.r, c.g, c.b});
    s.insert(s.end(), std::begin(used_values[i].s), std::end(used_values[i].s));
    owner.push_back(par::owner_of(retiled.rank_offsets, ids[i]));
  }
  io::SurfacePiece piece{xyz, triangles, {}, {}};
  piece.point_fields = {{"color", 3, std::span<const double>(colour)},
                        {"s", 3, std::span<const double>(s)},
                        {"vertex_id", 1, std::span<const std::int64_t>(ids)},
                        {"rank", 1, std::span<const std::int32_t>(owner)}};
  const std::string name = log::cat("level", level, "_pass", int(pass));
  io::write_parallel_surface(comm_, output_dir_ / "levels", name, piece, io::SurfaceFormat::vtp);
  series_.add(time_of(levels, level, pass), "levels/" + name + ".pvtp");
}

} // namespace texsim::pipelines::surface_synthesis
