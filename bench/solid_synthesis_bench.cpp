// The solid_synthesis pipeline's stages on the thesis' sizes: appearance-space features of a 64^3
// exemplar (all Gaussian-stack levels; the thesis took 31-49 s) and the pyramid synthesis of a
// 128^3 result from it (the thesis took 7-10 hours). The similarity sets the synthesis needs are
// read from --cache when present (scripts/bench similarity-set times that step), else computed
// once and stored there. Prints one JSON object on rank 0: medians over --repeats runs, each timed
// between MPI barriers, and the peak memory per rank.
// Sample run:
//   OMP_NUM_THREADS=1 mpirun -n 2 build/release/bench/solid_synthesis_bench --repeats 3
#include "bench_timing.hpp"
#include "core/log.hpp"
#include "par/petsc_session.hpp"
#include "pipelines/solid_synthesis/appearance_space.hpp"
#include "pipelines/solid_synthesis/pyramid_synthesizer.hpp"
#include "pipelines/solid_synthesis/similarity_set_cache.hpp"
#include "pipelines/solid_synthesis/synthesis_exemplar.hpp"
#include "vol/procedural_exemplars.hpp"

#include <mpi.h>
#include <nlohmann/json.hpp>
#include <omp.h>

#include <iostream>
#include <string>
#include <vector>

namespace {

using namespace texsim::pipelines::solid_synthesis;
using texsim::par::Comm;

struct BenchSettings {
  int exemplar = 64;
  int size = 128;
  int passes = 2;
  int repeats = 3;
  std::string cache = "build/release/bench/similarity-set-cache";
};

BenchSettings parse_arguments(int argc, char** argv) {
  BenchSettings settings;
  for (int i = 1; i + 1 < argc; ++i) {
    const std::string flag = argv[i];
    if (flag == "--exemplar")
      settings.exemplar = std::stoi(argv[++i]);
    else if (flag == "--size")
      settings.size = std::stoi(argv[++i]);
    else if (flag == "--passes")
      settings.passes = std::stoi(argv[++i]);
    else if (flag == "--repeats")
      settings.repeats = std::stoi(argv[++i]);
    else if (flag == "--cache")
      settings.cache = argv[++i];
  }
  return settings;
}

int levels_for(int size) {
  int levels = 0;
  while ((1 << levels) < size)
    ++levels;
  return levels;
}

} // namespace

int main(int argc, char** argv) {
  texsim::par::PetscSession session(argc, argv);
  const Comm comm = texsim::par::world();
  texsim::log::init(comm.rank, /*quiet=*/true); // stdout holds the JSON only
  const BenchSettings settings = parse_arguments(argc, argv);
  const auto exemplar =
      texsim::vol::to_channels(texsim::vol::marble_exemplar(settings.exemplar, 1));

  AppearanceSpace space;
  std::vector<double> feature_times;
  for (int r = 0; r < settings.repeats; ++r)
    feature_times.push_back(texsim::bench::timed(
        comm, [&] { space = build_appearance_space(comm, exemplar, AppearanceOptions{}); }));

  const int levels = levels_for(settings.size);
  std::vector<SimilaritySets> sets(space.levels.size());
  int computed = 0;
  const double sets_s = texsim::bench::timed(comm, [&] {
    for (const int s : corrected_stack_levels(space, levels)) {
      const std::string key = similarity_cache_key(space.levels[s].features, SimilarityOptions{});
      const auto file = std::filesystem::path(settings.cache) / ("similarity_sets_" + key + ".h5");
      if (auto cached = load_similarity_sets(comm, file, key)) {
        sets[s] = std::move(*cached);
        continue;
      }
      sets[s] = build_similarity_sets(comm, space.levels[s].features, SimilarityOptions{});
      save_similarity_sets(comm, file, key, sets[s]);
      ++computed;
    }
  });

  SynthesisOptions options;
  options.levels = levels;
  options.correction_passes = settings.passes;
  const PyramidSynthesizer synthesizer(comm, make_synthesis_exemplar(space, sets), options,
                                       nullptr);
  std::vector<double> synthesis_times;
  nlohmann::json level_times = nlohmann::json::array();
  for (int r = 0; r < settings.repeats; ++r) {
    std::vector<double> per_level;
    synthesis_times.push_back(texsim::bench::timed(comm, [&] {
      LevelStats stats;
      double start = MPI_Wtime();
      CoordinateSlab slab = synthesizer.first_level(stats);
      for (int level = 1; level <= levels; ++level) {
        slab = *synthesizer.next_level(slab, stats); // no stop check: always a level
        per_level.push_back(MPI_Wtime() - start);
        start = MPI_Wtime();
      }
    }));
    if (r == 0)
      level_times = per_level;
  }
  const double synthesis_s = texsim::bench::median(synthesis_times);
  const double memory_mb = texsim::bench::peak_memory_mb(comm);
  if (comm.is_root()) {
    const double voxels = double(1 << levels) * (1 << levels) * (1 << levels);
    const nlohmann::json out = {{"ranks", comm.size},
                                {"threads", omp_get_max_threads()},
                                {"exemplar", settings.exemplar},
                                {"size", 1 << levels},
                                {"passes", settings.passes},
                                {"features_s", texsim::bench::median(feature_times)},
                                {"similarity_sets_s", sets_s},
                                {"similarity_sets_computed_levels", computed},
                                {"synthesis_s", synthesis_s},
                                {"synthesis_level_s", level_times},
                                {"voxels_per_s", voxels / synthesis_s},
                                {"vm_hwm_mb_max", memory_mb}};
    std::cout << out.dump() << std::endl;
  }
  return 0;
}
