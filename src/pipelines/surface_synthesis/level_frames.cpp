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
  const std::int64_t first = retiled.rank_offsets[std::size_t(comm_.rank)];
  const std::int64_t end = retiled.rank_offsets[std::size_t(comm_.rank) + 1];
  std::vector<std::int32_t> local_of(retiled.mesh.positions.size(), -1);
  std::vector<std::int64_t> triangles;
  std::vector<std::int32_t> used;
  for (const auto& t : retiled.mesh.triangles) {
    const std::int32_t smallest = std::min({t[0], t[1], t[2]});
    if (smallest < first || smallest >= end)
      continue;
    for (const auto v : t)
      if (local_of[std::size_t(v)] < 0) {
        local_of[std::size_t(v)] = 0;
        used.push_back(v);
      }
  }
  std::sort(used.begin(), used.end());
  for (std::size_t i = 0; i < used.size(); ++i)
    local_of[std::size_t(used[i])] = std::int32_t(i);
  for (const auto& t : retiled.mesh.triangles)
    if (const std::int32_t smallest = std::min({t[0], t[1], t[2]});
        smallest >= first && smallest < end)
      for (const auto v : t)
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
  const std::vector<std::int64_t> ids(used.begin(), used.end());
  const auto used_values = par::fetch_from_owners(comm_, retiled.rank_offsets, std::span(ids),
                                                  std::span<const CornerValues>(run_values));
  std::vector<double> xyz, colour, s;
  std::vector<std::int32_t> owner;
  for (std::size_t i = 0; i < used.size(); ++i) {
    const auto v = std::size_t(used[i]);
    const auto& p = retiled.mesh.positions[v];
    xyz.insert(xyz.end(), {p.x(), p.y(), p.z()});
    const auto& c = used_values[i].colour;
    colour.insert(colour.end(), {c.r, c.g, c.b});
    s.insert(s.end(), std::begin(used_values[i].s), std::end(used_values[i].s));
    owner.push_back(par::owner_of(retiled.rank_offsets, std::int64_t(v)));
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
