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

/// A level's colours: every vertex on every rank (geometry is replicated for now), and the
/// exemplar pixel each took (-1: not synthesised, a random start).
struct LevelColours {
  std::vector<img::Rgb> colours;
  std::vector<std::int32_t> pixels;
};

class LevelSynthesizer {
public:
  /// Builds the exemplar tables and search structures of both passes of `level` (a pass that
  /// reads no sample is skipped: the coarsest level keeps its random colours). `rank_offsets` are
  /// the owned runs of the level's vertex ids. Collective (halo lists).
  LevelSynthesizer(const par::Comm& comm, const LevelStencils& stencils,
                   std::span<const std::int64_t> rank_offsets,
                   const std::vector<img::RgbImage>& pyramid, int level,
                   const NeighbourhoodTemplate& layout, SearchMethod method, ExemplarBorder border);
  ~LevelSynthesizer();

  /// Whether `pass` reads any sample on this level.
  bool runs(Pass pass) const;

  /// Synthesises classes [first_class, order.classes) of `pass` into `current` (reading
  /// `coarser`, the finished level below); `after_class(c)` runs on every rank after class c
  /// (checkpoints, stop checks). Collective.
  void run_pass(Pass pass, const SynthesisOrder& order, std::int32_t first_class,
                LevelColours& current, const LevelColours* coarser,
                const std::function<void(std::int32_t)>& after_class) const;

  /// Mean distance from each vertex's full (pass 2) neighbourhood to the nearest exemplar
  /// neighbourhood, exact, divided by the spread of the exemplar neighbourhoods (RMS distance to
  /// their mean): 0 when every neighbourhood occurs in the exemplar. Vertices with uncovered
  /// samples (boundaries, folds) are left out: their mean-filled samples are not texture, and
  /// their share is reported as the uncovered fraction. Collective.
  double neighbourhood_error(const LevelColours& current, const LevelColours* coarser) const;

  /// The neighbourhood of owned vertex `local` as `pass` reads it (samples x RGB), and the search
  /// it goes to: for benchmarks comparing searches on real queries.
  void neighbourhood(Pass pass, std::int64_t local, const LevelColours& current,
                     const LevelColours* coarser, std::vector<double>& out) const;
  const NeighbourhoodSearch& search(Pass pass) const;

  /// Bytes of the exemplar tables and search structures on this rank.
  std::size_t memory_bytes() const;

private:
  struct PassData;
  void query(const PassData& data, std::int64_t local, const LevelColours& current,
             const LevelColours* coarser, std::vector<double>& out) const;
  void send_class(const std::vector<std::int64_t>& members, LevelColours& current) const;

  par::Comm comm_;
  const LevelStencils& stencils_;
  const img::RgbImage& image_;
  img::Rgb current_mean_, coarser_mean_;
  std::vector<std::unique_ptr<PassData>> passes_; ///< [0] pass 1, [1] pass 2
  /// Per owned vertex, the other ranks whose current-part stencils read it (CSR).
  std::vector<std::int64_t> reader_offsets_;
  std::vector<int> readers_;
};

} // namespace texsim::pipelines::surface_synthesis
