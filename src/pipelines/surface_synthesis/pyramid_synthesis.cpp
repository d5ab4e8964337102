#include "pipelines/surface_synthesis/pyramid_synthesis.hpp"

#include "core/rng.hpp"
#include "pipelines/surface_synthesis/level_stencils.hpp"

#include <mpi.h>

#include <algorithm>
#include <array>

namespace texsim::pipelines::surface_synthesis {
namespace {

constexpr std::uint32_t kRandomStartStream = 0x5302;

/// How many distinct colours the level's vertices hold: each rank marks the exemplar pixels its
/// own vertices copy, the marks are OR-ed over ranks, and the marked pixels' colours are counted
/// (an exemplar may hold one colour at many pixels). Collective.
std::int64_t distinct_colours(const par::Comm& comm, const LevelColours& colours,
                              const img::RgbImage& exemplar) {
  std::vector<std::uint8_t> used(exemplar.size(), 0);
  for (const std::int32_t pixel : colours.pixels)
    used[std::size_t(pixel)] = 1;
  MPI_Allreduce(MPI_IN_PLACE, used.data(), int(used.size()), MPI_UINT8_T, MPI_BOR, comm.raw);
  std::vector<std::array<float, 3>> palette;
  for (std::size_t p = 0; p < used.size(); ++p)
    if (used[p]) {
      const img::Rgb& c = exemplar.data()[p];
      palette.push_back({c.r, c.g, c.b});
    }
  std::sort(palette.begin(), palette.end());
  return std::unique(palette.begin(), palette.end()) - palette.begin();
}

} // namespace

std::vector<LevelColours> random_start(const std::vector<RetiledLevel>& pyramid,
                                       const std::vector<img::RgbImage>& exemplar,
                                       std::uint64_t seed, int rank) {
  const CounterRng rng(seed, kRandomStartStream);
  std::vector<LevelColours> colours(pyramid.size());
  for (std::size_t k = 0; k < pyramid.size(); ++k) {
    const auto first = std::size_t(pyramid[k].rank_offsets[std::size_t(rank)]);
    const auto count = std::size_t(pyramid[k].rank_offsets[std::size_t(rank) + 1]) - first;
    const auto pixels = exemplar[k].size();
    colours[k].colours.resize(count);
    colours[k].pixels.resize(count);
    for (std::size_t i = 0; i < count; ++i) {
      const auto pixel = std::size_t(rng.uniform(first + i, std::uint32_t(k)) * double(pixels));
      colours[k].pixels[i] = std::int32_t(pixel);
      colours[k].colours[i] = exemplar[k].data()[pixel];
    }
  }
  return colours;
}

PyramidSynthesisReport synthesize_pyramid(const par::Comm& comm, const PyramidSynthesisInput& input,
                                          std::vector<LevelColours>& colours,
                                          const std::optional<SynthesisPosition>& resume,
                                          const PyramidSynthesisHooks& hooks, StageTimers& timers) {
  PyramidSynthesisReport report;
  const int levels = int(input.pyramid.size());
  for (int k = levels - 1; k >= 0; --k) {
    if (resume && k > resume->level)
      continue; // finished before the checkpoint
    const auto K = std::size_t(k);
    const auto& level = input.pyramid[K];
    const bool has_coarser = k + 1 < levels;
    const auto layout = NeighbourhoodTemplate::from_shape(input.shapes[K], has_coarser);
    const std::int64_t first = level.rank_offsets[std::size_t(comm.rank)];
    const std::int64_t owned = level.rank_offsets[std::size_t(comm.rank) + 1] - first;
    LevelStencils stencils = [&] {
      auto stage = timers.scope("stencils");
      const bool reads_coarser = has_coarser && !layout.coarser.empty();
      return build_level_stencils(comm, level, level.positions, level.normals, input.directions[K],
                                  reads_coarser ? &input.pyramid[K + 1] : nullptr,
                                  reads_coarser ? std::span(input.parents[K])
                                                : std::span<const ParentFace>(),
                                  layout, first, owned);
    }();
    std::optional<LevelSynthesizer> synthesizer;
    {
      auto stage = timers.scope("synthesis");
      synthesizer.emplace(comm, std::move(stencils), level.rank_offsets,
                          has_coarser ? std::span(input.pyramid[K + 1].rank_offsets)
                                      : std::span<const std::int64_t>(),
                          input.exemplar, k, layout, input.method, input.border, input.seed);
      synthesizer->read_colours(colours[K], has_coarser ? &colours[K + 1] : nullptr);
    }
    report.search_bytes = std::max(report.search_bytes, synthesizer->memory_bytes());
    std::int64_t halo =
        std::int64_t(synthesizer->halo().size() + synthesizer->coarser_reads().size());
    MPI_Allreduce(MPI_IN_PLACE, &halo, 1, MPI_INT64_T, MPI_MAX, comm.raw);
    report.halo_vertices = std::max(report.halo_vertices, halo);
    if (k == 0 && !resume && input.measure_quality)
      report.random_start_error = synthesizer->neighbourhood_error();
    PyramidSynthesisReport::Level level_report;
    level_report.level = k;
    for (const Pass pass : {Pass::extrapolate, Pass::refine}) {
      const bool at_checkpoint = resume && k == resume->level;
      if (at_checkpoint && int(pass) < int(resume->pass))
        continue;
      const std::int32_t first_class =
          at_checkpoint && pass == resume->pass ? resume->next_class : 0;
      // Pass 1 on the coarsest level keeps the random colours (Wei-Levoy 3.2).
      if (synthesizer->runs(pass) && !(pass == Pass::extrapolate && !has_coarser)) {
        auto stage = timers.scope("synthesis");
        const std::int32_t classes = synthesizer->order(pass).classes;
        level_report.classes[int(pass) - 1] = classes;
        synthesizer->run_pass(pass, first_class, colours[K], [&](std::int32_t c) {
          if (hooks.after_class)
            hooks.after_class(k, pass, c, classes);
        });
      }
      if (hooks.after_pass)
        hooks.after_pass(k, pass);
    }
    const LevelStencils& sampled = synthesizer->stencils();
    std::int64_t counts[2] = {sampled.uncovered(),
                              std::int64_t(sampled.current.size() + sampled.coarser.size())};
    MPI_Allreduce(MPI_IN_PLACE, counts, 2, MPI_INT64_T, MPI_SUM, comm.raw);
    level_report.uncovered_fraction = counts[1] > 0 ? double(counts[0]) / double(counts[1]) : 0;
    level_report.distinct_colours = distinct_colours(comm, colours[K], input.exemplar[K]);
    report.levels.push_back(level_report);
    if (k == 0 && input.measure_quality)
      report.neighbourhood_error = synthesizer->neighbourhood_error();
  }
  return report;
}

} // namespace texsim::pipelines::surface_synthesis
