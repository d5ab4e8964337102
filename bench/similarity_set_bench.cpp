// Exact k-coherence similarity sets (build_similarity_sets) on a --size^3 exemplar in appearance
// space: the pipeline's own features, i.e. the PCA (--dimensions components) of the 5^3 x RGB
// neighbourhoods of a procedural exemplar (--exemplar, default marble: smooth veins, so near
// neighbours cluster spatially and the exclusion windows matter). Reports the median wall time over
// --repeats builds, distance evaluations per second, the bound a GEMM formulation could reach (2 d
// N^2 flops at the OpenBLAS sgemm rate measured in this run on all cores), exactness on --sample
// voxels against a brute-force search ("exact", null with --sample 0), with --compare-scan 1
// whether every voxel's set equals the scan's ("equals_scan"), peak memory and the N^2
// extrapolation to a 256^3 exemplar (meaningful for the scan). --search tree (default) or scan.
// Prints one JSON object on rank 0.
// Sample run:
//   OMP_NUM_THREADS=1 mpirun -n 2 build/release/bench/similarity_set_bench --size 64 --repeats 3
#include "bench_timing.hpp"
#include "core/float_distance_scan.hpp"
#include "core/log.hpp"
#include "core/rng.hpp"
#include "par/petsc_session.hpp"
#include "pipelines/solid_synthesis/appearance_space.hpp"
#include "pipelines/solid_synthesis/similarity_sets.hpp"
#include "vol/procedural_exemplars.hpp"

#include <cblas.h>
#include <mpi.h>
#include <nlohmann/json.hpp>
#include <omp.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdlib>
#include <iostream>
#include <string>
#include <vector>

namespace {
using texsim::par::Comm;
using namespace texsim::pipelines::solid_synthesis;
using texsim::bench::median;
using texsim::bench::peak_memory_mb;
using texsim::bench::timed;

struct BenchSettings {
  std::string exemplar = "marble"; ///< marble | wood | particles | bricks | noise
  int size = 64;
  int dimensions = 8;
  SimilarityOptions options; ///< k = 3, window = 7, periodic: the thesis' settings
  int repeats = 3;
  int sample = 500; ///< voxels checked against the brute-force search (0: no check)
  int gemm_size = 3072;
  bool compare_scan = false; ///< also build the sets by the scan once and compare every voxel
};

BenchSettings parse_arguments(int argc, char** argv) {
  BenchSettings s;
  s.options.search = ShortlistSearch::tree; // measured as such, not as `auto` picks
  for (int i = 1; i + 1 < argc; i += 2) {
    const std::string flag = argv[i];
    if (flag == "--exemplar") {
      s.exemplar = argv[i + 1];
      continue;
    }
    if (flag == "--search") {
      const std::string search = argv[i + 1];
      if (search != "tree" && search != "scan") {
        std::cerr << "--search: expected tree or scan, got " << search << "\n";
        std::exit(2);
      }
      s.options.search = search == "tree" ? ShortlistSearch::tree : ShortlistSearch::scan;
      continue;
    }
    const int value = std::stoi(argv[i + 1]);
    if (flag == "--size")
      s.size = value;
    else if (flag == "--dimensions")
      s.dimensions = value;
    else if (flag == "--k")
      s.options.k = value;
    else if (flag == "--window")
      s.options.window = value;
    else if (flag == "--repeats")
      s.repeats = value;
    else if (flag == "--sample")
      s.sample = value;
    else if (flag == "--gemm-size")
      s.gemm_size = value;
    else if (flag == "--compare-scan")
      s.compare_scan = value != 0;
    else {
      std::cerr << "unknown option " << flag << "\n";
      std::exit(2);
    }
  }
  return s;
}

double sum_over_ranks(const Comm& comm, double value) {
  double sum = 0;
  MPI_Allreduce(&value, &sum, 1, MPI_DOUBLE, MPI_SUM, comm.raw);
  return sum;
}

/// Single-precision GEMM rate of the whole job, GFLOP/s: every rank multiplies two n x n matrices
/// at once with OpenBLAS on its OpenMP threads; best of three, summed over ranks. Collective.
double sgemm_gflops(const Comm& comm, int n) {
  openblas_set_num_threads(omp_get_max_threads());
  std::vector<float> a(static_cast<std::size_t>(n) * n), b(a.size()), c(a.size());
  const texsim::CounterRng rng(1, 3);
  for (std::size_t i = 0; i < a.size(); ++i) {
    a[i] = static_cast<float>(rng.uniform(i, 0));
    b[i] = static_cast<float>(rng.uniform(i, 1));
  }
  double best = 0;
  for (int run = 0; run < 3; ++run) {
    MPI_Barrier(comm.raw);
    const double start = MPI_Wtime();
    cblas_sgemm(CblasRowMajor, CblasNoTrans, CblasNoTrans, n, n, n, 1.0f, a.data(), n, b.data(), n,
                0.0f, c.data(), n);
    const double seconds = MPI_Wtime() - start;
    best = std::max(best, 2.0 * n * n * static_cast<double>(n) / seconds / 1e9);
  }
  return sum_over_ranks(comm, best);
}

/// C_1 .. C_k of voxel p by brute force: every voxel ranked by (double distance, index), then
/// the first voxels that lie outside the windows of those already taken.
std::vector<std::int32_t> brute_force_set(const texsim::vol::ChannelGrid& features,
                                          const SimilarityOptions& options, std::int32_t p) {
  const auto dims = features.dims();
  const auto n = static_cast<std::int32_t>(features.voxel_count());
  const auto fp = features.voxel(static_cast<std::size_t>(p));
  std::vector<std::pair<double, std::int32_t>> ranked(static_cast<std::size_t>(n));
  for (std::int32_t q = 0; q < n; ++q) {
    const auto fq = features.voxel(static_cast<std::size_t>(q));
    double sum = 0;
    for (std::size_t c = 0; c < fp.size(); ++c) {
      const double diff = static_cast<double>(fq[c]) - static_cast<double>(fp[c]);
      sum += diff * diff;
    }
    ranked[static_cast<std::size_t>(q)] = {sum, q};
  }
  std::sort(ranked.begin(), ranked.end());
  const auto at = [&](std::int32_t v) {
    return std::array<int, 3>{v % dims.nx, v / dims.nx % dims.ny, v / (dims.nx * dims.ny)};
  };
  const auto inside = [&](std::int32_t a, std::int32_t b) {
    const auto pa = at(a), pb = at(b);
    const int sizes[3] = {dims.nx, dims.ny, dims.nz};
    for (int axis = 0; axis < 3; ++axis) {
      const int d = std::abs(pa[axis] - pb[axis]);
      if ((options.periodic ? std::min(d, sizes[axis] - d) : d) > options.window / 2)
        return false;
    }
    return true;
  };
  std::vector<std::int32_t> set{p};
  for (const auto& [distance, q] : ranked) {
    if (static_cast<int>(set.size()) == options.k)
      break;
    if (std::none_of(set.begin(), set.end(), [&](std::int32_t c) { return inside(c, q); }))
      set.push_back(q);
  }
  while (static_cast<int>(set.size()) < options.k)
    set.push_back(set.back());
  return set;
}

/// Whether `sample` voxels spread over the grid (split across ranks) match brute force.
/// Collective.
bool sampled_exact(const Comm& comm, const texsim::vol::ChannelGrid& features,
                   const SimilarityOptions& options, const SimilaritySets& sets, int sample) {
  const auto n = static_cast<std::int64_t>(features.voxel_count());
  const texsim::CounterRng rng(5, 9);
  int wrong = 0;
  for (int i = comm.rank; i < sample; i += comm.size) {
    const auto v = static_cast<std::int32_t>(rng.uniform(static_cast<std::uint64_t>(i), 0) * n);
    const auto expected = brute_force_set(features, options, v);
    wrong += !std::equal(expected.begin(), expected.end(),
                         sets.candidates.begin() + static_cast<std::int64_t>(v) * sets.k);
  }
  return sum_over_ranks(comm, wrong) == 0;
}

texsim::vol::RgbGrid procedural_exemplar(const std::string& name, int n) {
  using namespace texsim::vol;
  if (name == "marble")
    return marble_exemplar(n, 1);
  if (name == "wood")
    return wood_exemplar(n, 1);
  if (name == "particles")
    return particle_exemplar(n, 1);
  if (name == "bricks")
    return brick_exemplar(n, 1);
  if (name == "noise")
    return noise_exemplar(n, 1);
  std::cerr << "unknown exemplar " << name << "\n";
  std::exit(2);
}

} // namespace

int main(int argc, char** argv) {
  texsim::par::PetscSession session(argc, argv);
  const Comm comm = texsim::par::world();
  texsim::log::init(comm.rank, /*quiet=*/true); // stdout holds the JSON only
  const BenchSettings settings = parse_arguments(argc, argv);

  AppearanceSpace space;
  const double appearance_s = timed(comm, [&] {
    const auto exemplar =
        texsim::vol::to_channels(procedural_exemplar(settings.exemplar, settings.size));
    space = build_appearance_space(exemplar, {settings.dimensions, 5, ExemplarBorder::toroidal});
  });
  const texsim::vol::ChannelGrid& features = space.levels.front().features;

  std::vector<double> walls;
  SimilaritySets sets;
  for (int r = 0; r < settings.repeats; ++r)
    walls.push_back(
        timed(comm, [&] { sets = build_similarity_sets(comm, features, settings.options); }));
  const double memory_mb = peak_memory_mb(comm);
  const nlohmann::json exact =
      settings.sample > 0 ? nlohmann::json(sampled_exact(comm, features, settings.options, sets,
                                                         settings.sample))
                          : nlohmann::json(nullptr); // not checked
  nlohmann::json equals_scan = nullptr;              // not compared
  if (settings.compare_scan) {
    SimilarityOptions scan = settings.options;
    scan.search = ShortlistSearch::scan;
    equals_scan = build_similarity_sets(comm, features, scan).candidates == sets.candidates;
  }
  const double gflops = sgemm_gflops(comm, settings.gemm_size);

  if (comm.is_root()) {
    const double n = static_cast<double>(features.voxel_count());
    const double wall = median(walls);
    const double flops = 2.0 * features.channels() * n * n;
    const nlohmann::json out = {
        {"exemplar", settings.exemplar + " " + std::to_string(settings.size) +
                         "^3, appearance space (PCA of 5^3 x RGB neighbourhoods)"},
        {"voxels", features.voxel_count()},
        {"dimensions", features.channels()},
        {"k", settings.options.k},
        {"window", settings.options.window},
        {"periodic", settings.options.periodic},
        {"search", settings.options.search == ShortlistSearch::tree ? "tree" : "scan"},
        {"scan_isa", texsim::scan_isa_name(texsim::best_scan_isa())},
        {"ranks", comm.size},
        {"threads", omp_get_max_threads()},
        {"repeats", settings.repeats},
        {"wall_s", wall},
        {"wall_s_runs", walls},
        {"distance_evals_per_s", n * n / wall},
        {"sgemm_gflops", gflops},
        {"gemm_flops", flops},
        {"gemm_bound_s", flops / (gflops * 1e9)},
        {"over_gemm_bound", wall / (flops / (gflops * 1e9))},
        {"exact", exact},
        {"equals_scan", equals_scan},
        {"sampled_voxels", settings.sample},
        {"vm_hwm_mb_max", memory_mb},
        {"extrapolated_256_s", wall * std::pow(std::pow(256.0, 3) / n, 2)},
        {"appearance_s", appearance_s}};
    std::cout << out.dump(1) << std::endl;
  }
  return 0;
}
