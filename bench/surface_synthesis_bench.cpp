// Wei-Levoy surface synthesis on the Fig. 7 sphere (24,576 retiled vertices, 49,148 faces): a
// 4-level pyramid, a 64 x 64 exemplar (data/images/pebbles05.png reduced 4 times; the procedural
// lattice when it is missing, flagged "exemplar_fallback"), neighbourhoods {1x1,1}, {3x3,2},
// {5x5,2}, {7x7,2}. Times the orientation relaxation (2-way, --sweeps sweeps per level, inherited
// from the parent level as the pipeline does) and the synthesis with each search method (stencils,
// classes, both passes of every level; hierarchy and relaxation excluded), medians over --repeats.
// The neighbourhood error of each method's result (exact nearest exemplar neighbourhood, over the
// exemplar's spread) and, on the finest level's pass-2 queries of the TSVQ result, the fraction
// where TSVQ returns the exact nearest row. Paper (450 MHz Pentium II): relaxation 85 s,
// exhaustive 695 s, TSVQ 82 s.
// Prints one JSON object on rank 0. Sample run:
//   OMP_NUM_THREADS=1 mpirun -n 2 build/release/bench/surface_synthesis_bench --repeats 3
#include "bench_timing.hpp"
#include "core/log.hpp"
#include "geom/generators.hpp"
#include "pipelines/surface_synthesis/exemplar_pyramid.hpp"
#include "pipelines/surface_synthesis/level_stencils.hpp"
#include "pipelines/surface_synthesis/level_synthesizer.hpp"
#include "pipelines/surface_synthesis/orientation_relaxation.hpp"
#include "pipelines/surface_synthesis/parent_faces.hpp"
#include "pipelines/surface_synthesis/pyramid_synthesis.hpp"
#include "pipelines/surface_synthesis/run_star.hpp"

#include <mpi.h>
#include <nlohmann/json.hpp>

#include <filesystem>
#include <iostream>
#include <string>

namespace {
using namespace texsim::pipelines::surface_synthesis;
using texsim::bench::max_over_ranks;
using texsim::bench::median;
using texsim::bench::peak_memory_mb;
using texsim::bench::timed;
using texsim::par::Comm;
namespace geom = texsim::geom;

struct BenchSettings {
  std::int64_t vertices = 24576;
  int levels = 4;
  int icosphere_level = 6;
  int sweeps = 30;
  int repeats = 3;
  std::string exemplar = "data/images/pebbles05.png";
};

BenchSettings parse(int argc, char** argv) {
  BenchSettings s;
  for (int i = 1; i + 1 < argc; i += 2) {
    const std::string key = argv[i], value = argv[i + 1];
    if (key == "--vertices")
      s.vertices = std::stoll(value);
    else if (key == "--levels")
      s.levels = std::stoi(value);
    else if (key == "--icosphere-level")
      s.icosphere_level = std::stoi(value);
    else if (key == "--sweeps")
      s.sweeps = std::stoi(value);
    else if (key == "--repeats")
      s.repeats = std::stoi(value);
    else if (key == "--exemplar")
      s.exemplar = value;
    else
      throw std::runtime_error("unknown option " + key);
  }
  return s;
}

/// The orientation of every level (this rank's run), coarse to fine, as the pipeline's `relax`
/// mode computes it.
std::vector<std::vector<geom::Vec3>> relaxed(const Comm& comm,
                                             const std::vector<RetiledLevel>& pyramid,
                                             const std::vector<std::vector<ParentFace>>& parents,
                                             int sweeps) {
  const int levels = int(pyramid.size());
  std::vector<std::vector<geom::Vec3>> directions(pyramid.size());
  for (int k = levels - 1; k >= 0; --k) {
    const auto K = std::size_t(k);
    const std::int64_t first = pyramid[K].rank_offsets[std::size_t(comm.rank)];
    const auto& normals = pyramid[K].normals; // this rank's run
    const auto random = random_directions(normals, 1, k, first);
    std::optional<CoarserOrientation> coarser;
    directions[K] = random;
    if (k + 1 < levels) {
      coarser = coarser_orientation(comm, parents[K], pyramid[K + 1].rank_offsets,
                                    directions[K + 1], pyramid[K + 1].normals);
      directions[K] = inherited_directions(normals, *coarser, 2, random);
    }
    relax_directions(comm, pyramid[K].rank_offsets, run_rings(pyramid[K], comm.rank), normals,
                     coarser ? &*coarser : nullptr, 2, sweeps, directions[K]);
  }
  return directions;
}

} // namespace

int main(int argc, char** argv) {
  MPI_Init(&argc, &argv);
  const Comm comm = texsim::par::world();
  texsim::log::init(comm.rank, /*quiet=*/true); // stdout holds the JSON only
  const auto settings = parse(argc, argv);
  nlohmann::json out;

  ExemplarSettings exemplar_settings;
  const bool fallback = !std::filesystem::exists(settings.exemplar);
  if (fallback) {
    exemplar_settings.procedural = ProceduralExemplar::lattice;
    exemplar_settings.size = 64;
    exemplar_settings.periods = 1;
  } else {
    exemplar_settings.image = settings.exemplar;
    exemplar_settings.reduce = 4;
  }
  const auto exemplar = exemplar_pyramid(load_exemplar(exemplar_settings, 1), settings.levels,
                                         ExemplarBorder::toroidal);

  MeshPyramidSettings pyramid_settings;
  pyramid_settings.finest_count = settings.vertices;
  pyramid_settings.levels = settings.levels;
  std::vector<RetiledLevel> pyramid;
  const double hierarchy_s =
      max_over_ranks(comm, timed(comm, [&] {
                       pyramid = build_mesh_pyramid(comm, geom::icosphere(settings.icosphere_level),
                                                    1, pyramid_settings);
                     }));
  std::vector<std::vector<ParentFace>> parents(pyramid.size());
  for (std::size_t k = 0; k < pyramid.size(); ++k) {
    if (k + 1 < pyramid.size())
      parents[k] = find_parent_faces(comm, pyramid[k], pyramid[k + 1]);
  }

  std::vector<double> relax_s;
  std::vector<std::vector<geom::Vec3>> directions;
  for (int r = 0; r < settings.repeats; ++r)
    relax_s.push_back(max_over_ranks(
        comm, timed(comm, [&] { directions = relaxed(comm, pyramid, parents, settings.sweeps); })));

  PyramidSynthesisInput input{pyramid, directions, parents, exemplar};
  for (int k = 0; k < settings.levels; ++k) {
    const std::vector<NeighbourhoodShape> paper{{7, 7, 2}, {5, 5, 2}, {3, 3, 2}, {1, 1, 1}};
    input.shapes.push_back(k + 1 == settings.levels ? NeighbourhoodShape{1, 1, 1}
                                                    : paper[std::min<std::size_t>(k, 2)]);
  }
  nlohmann::json methods = nlohmann::json::object();
  std::vector<LevelColours> tsvq_colours;
  for (const auto& [name, method] :
       {std::pair{"exact", SearchMethod::exhaustive}, std::pair{"tsvq", SearchMethod::tsvq},
        std::pair{"pruned", SearchMethod::pruned}}) {
    input.method = method;
    input.measure_quality = false;
    std::vector<double> seconds;
    std::vector<LevelColours> colours;
    for (int r = 0; r < settings.repeats; ++r) {
      colours = random_start(pyramid, exemplar, 1, comm.rank);
      texsim::StageTimers timers;
      seconds.push_back(max_over_ranks(comm, timed(comm, [&] {
                                         synthesize_pyramid(comm, input, colours, std::nullopt, {},
                                                            timers);
                                       })));
    }
    // The error of this method's result, measured once with an exact search.
    input.measure_quality = true;
    colours = random_start(pyramid, exemplar, 1, comm.rank);
    texsim::StageTimers timers;
    const auto report = synthesize_pyramid(comm, input, colours, std::nullopt, {}, timers);
    methods[name] = {{"synthesis_s", median(seconds)},
                     {"neighbourhood_error", report.neighbourhood_error},
                     {"random_start_error", report.random_start_error},
                     {"search_bytes", report.search_bytes}};
    if (method == SearchMethod::tsvq)
      tsvq_colours = colours;
  }

  // TSVQ against the exact search on the finest level's pass-2 queries of the TSVQ result.
  {
    const auto& level = pyramid[0];
    const auto layout = NeighbourhoodTemplate::from_shape(input.shapes[0], pyramid.size() > 1);
    const auto first = level.rank_offsets[std::size_t(comm.rank)];
    const auto owned = level.rank_offsets[std::size_t(comm.rank) + 1] - first;
    auto stencils = build_level_stencils(comm, level, level.positions, level.normals, directions[0],
                                         &pyramid[1], parents[0], layout, first, owned);
    LevelSynthesizer tsvq(comm, std::move(stencils), level.rank_offsets, pyramid[1].rank_offsets,
                          exemplar, 0, layout, SearchMethod::tsvq, ExemplarBorder::toroidal, 1);
    tsvq.read_colours(tsvq_colours[0], &tsvq_colours[1]);
    const auto exact =
        make_neighbourhood_search(SearchMethod::pruned, tsvq.search(Pass::refine).table());
    double counts[2] = {0, double(owned)};
    std::vector<double> q;
    for (std::int64_t local = 0; local < owned; ++local) {
      tsvq.neighbourhood(Pass::refine, local, q);
      counts[0] += tsvq.search(Pass::refine).nearest(q) == exact->nearest(q);
    }
    MPI_Allreduce(MPI_IN_PLACE, counts, 2, MPI_DOUBLE, MPI_SUM, comm.raw);
    out["tsvq_exact_fraction"] = counts[0] / counts[1];
  }

  out["ranks"] = comm.size;
  out["vertices"] = settings.vertices;
  out["triangles"] = pyramid[0].triangle_count();
  out["levels"] = settings.levels;
  out["exemplar"] = fallback ? "lattice 64" : settings.exemplar;
  out["exemplar_fallback"] = fallback;
  out["hierarchy_s"] = hierarchy_s;
  out["relax_s"] = median(relax_s);
  out["sweeps"] = settings.sweeps;
  out["methods"] = methods;
  out["peak_memory_mb"] = peak_memory_mb(comm);
  if (comm.rank == 0)
    std::cout << out.dump() << std::endl;
  MPI_Finalize();
  return 0;
}
