#pragma once
/// One level of Wei-Levoy's synthesis (Table 3, lines 7-9) on a rank's vertices: for every vertex
/// of a colour class, its neighbourhood is resampled from the stencils, the nearest exemplar
/// neighbourhood found, and the vertex takes that pixel's colour; after each class the owners send
/// the new colours to the ranks whose stencils read them.
#include "img/image.hpp"
#include "par/comm.hpp"
#include "pipelines/surface_synthesis/exemplar_neighbourhoods.hpp"
#include "pipelines/surface_synthesis/level_stencils.hpp"
#include "pipelines/surface_synthesis/neighbourhood_search.hpp"
#include "pipelines/surface_synthesis/synthesis_order.hpp"

#include <functional>
#include <memory>
#include <span>
#include <vector>

namespace texsim::pipelines::surface_synthesis {

/// A level's colours on this rank's run of its vertex ids (vertex first + i at i), and the exemplar
/// pixel each took.
struct LevelColours {
  std::vector<img::Rgb> colours;
  std::vector<std::int32_t> pixels;
};

class LevelSynthesizer {
public:
  /// Takes the stencils of this rank's run of `level` and builds, for both passes (a pass that
  /// reads no sample is skipped: the coarsest level keeps its random colours), the colour classes
  /// (synthesis_order with `seed`), the exemplar tables and the search structures. Then the halo:
  /// the other ranks' vertices the current-part samples read, and the coarser level's vertices the
  /// coarser-part samples read; the stencils' vertex ids are renumbered into those local arrays,
  /// so no rank holds a whole level's colours. `rank_offsets` and `coarser_offsets` are the owned
  /// runs of the level's and the coarser level's vertex ids (the latter empty without a coarser
  /// part). Collective.
  LevelSynthesizer(const par::Comm& comm, LevelStencils stencils,
                   std::span<const std::int64_t> rank_offsets,
                   std::span<const std::int64_t> coarser_offsets,
                   const std::vector<img::RgbImage>& pyramid, int level,
                   const NeighbourhoodTemplate& layout, SearchMethod method, ExemplarBorder border,
                   std::uint64_t seed);
  ~LevelSynthesizer();

  /// Whether `pass` reads any sample on this level.
  bool runs(Pass pass) const;
  /// The colour classes of a pass that runs.
  const SynthesisOrder& order(Pass pass) const;

  /// Reads the colours the stencils sample: `current`, this rank's run of the level (a random
  /// start or a checkpoint), its halo's from their owners, and the coarser samples' vertices from
  /// the owners of `coarser`, the finished coarser level's runs (null without a coarser part).
  /// Before the passes and the metric. Collective.
  void read_colours(const LevelColours& current, const LevelColours* coarser);

  /// Synthesises classes [first_class, order(pass).classes) of `pass` into `current` (this rank's
  /// run, as given to read_colours); `after_class(c)` runs on every rank after class c
  /// (checkpoints, stop checks). Collective.
  void run_pass(Pass pass, std::int32_t first_class, LevelColours& current,
                const std::function<void(std::int32_t)>& after_class);

  /// Mean distance from each vertex's full (pass 2) neighbourhood to the nearest exemplar
  /// neighbourhood, exact, divided by the spread of the exemplar neighbourhoods (RMS distance to
  /// their mean): 0 when every neighbourhood occurs in the exemplar. Vertices with uncovered
  /// samples (boundaries, folds) are left out: their mean-filled samples are not texture, and
  /// their share is reported as the uncovered fraction. Collective.
  double neighbourhood_error() const;

  /// The neighbourhood of owned vertex `local` as `pass` reads it (samples x RGB), and the search
  /// it goes to: for benchmarks comparing searches on real queries.
  void neighbourhood(Pass pass, std::int64_t local, std::vector<double>& out) const;
  const NeighbourhoodSearch& search(Pass pass) const;

  /// The stencils, their vertex ids local: [0, owned) the run, then the halo; coarser samples
  /// index the coarser vertices read.
  const LevelStencils& stencils() const { return stencils_; }
  /// The level's vertices read but owned elsewhere (local ids owned + i), and the coarser
  /// level's vertices read (local ids i), by increasing id.
  std::span<const std::int64_t> halo() const { return halo_; }
  std::span<const std::int64_t> coarser_reads() const { return coarser_reads_; }
  /// Bytes of the exemplar tables and search structures on this rank.
  std::size_t memory_bytes() const;

private:
  struct PassData;
  void localise_stencils();
  void find_readers();
  void query(const PassData& data, std::int64_t local, std::vector<double>& out) const;
  void send_class(const std::vector<std::int64_t>& members);

  par::Comm comm_;
  LevelStencils stencils_;
  std::span<const std::int64_t> rank_offsets_, coarser_offsets_;
  const img::RgbImage& image_;
  img::Rgb current_mean_, coarser_mean_;
  std::vector<std::unique_ptr<PassData>> passes_; ///< [0] pass 1, [1] pass 2
  std::vector<std::int64_t> halo_, coarser_reads_;
  std::vector<img::Rgb> colours_;         ///< the run's, then the halo's
  std::vector<img::Rgb> coarser_colours_; ///< at coarser_reads_
  /// Per owned vertex, the other ranks whose current-part stencils read it (CSR).
  std::vector<std::int64_t> reader_offsets_;
  std::vector<int> readers_;
};

} // namespace texsim::pipelines::surface_synthesis
