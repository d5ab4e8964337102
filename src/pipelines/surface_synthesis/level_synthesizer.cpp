#include "pipelines/surface_synthesis/level_synthesizer.hpp"

#include "core/error.hpp"
#include "par/fetch_from_owners.hpp"
#include "par/id_runs.hpp"
#include "par/record_exchange.hpp"

#include <mpi.h>

#include <algorithm>
#include <cmath>

namespace texsim::pipelines::surface_synthesis {

struct LevelSynthesizer::PassData {
  Pass pass;
  SynthesisOrder order;
  ExemplarNeighbourhoods exemplar;
  std::unique_ptr<NeighbourhoodSearch> search;
  std::unique_ptr<NeighbourhoodSearch> exact; ///< for the metric when `search` is approximate
};

namespace {

struct ReadRequest {
  std::int64_t id;
  std::int32_t reader;
};

struct ColourUpdate {
  std::int64_t id;
  float rgb[3];
};

/// Queries per search call (the exhaustive scan's register blocking takes 8 at a time).
constexpr std::size_t kBatch = 16;

void add_sample(const SampleWeights& sample, std::span<const img::Rgb> colours,
                const img::Rgb& uncovered, double* out) {
  if (!sample.covered()) {
    for (int ch = 0; ch < 3; ++ch)
      out[ch] = uncovered[ch];
    return;
  }
  for (int ch = 0; ch < 3; ++ch) {
    double value = 0;
    for (std::size_t k = 0; k < 3; ++k)
      value += double(sample.weights[k]) * colours[std::size_t(sample.vertices[k])][ch];
    out[ch] = value;
  }
}

/// The distinct vertex ids of `samples`' covered samples that `keep` accepts, increasing. The ids
/// are merged into the sorted distinct ones every so often, so the list never holds every
/// sample's three ids (there are tens of samples per distinct vertex).
template <class Keep>
std::vector<std::int64_t> sampled_vertices(std::span<const SampleWeights> samples, Keep keep) {
  constexpr std::size_t kMergeEvery = std::size_t{1} << 16;
  std::vector<std::int64_t> ids;
  std::size_t distinct = 0; // ids[0, distinct) are sorted and distinct
  const auto merge = [&] {
    const auto middle = ids.begin() + std::ptrdiff_t(distinct);
    std::sort(middle, ids.end());
    std::inplace_merge(ids.begin(), middle, ids.end());
    ids.erase(std::unique(ids.begin(), ids.end()), ids.end());
    distinct = ids.size();
  };
  for (const auto& sample : samples)
    if (sample.covered())
      for (const auto v : sample.vertices)
        if (keep(v)) {
          ids.push_back(v);
          if (ids.size() >= 2 * distinct + kMergeEvery)
            merge();
        }
  merge();
  return ids;
}

std::int32_t index_in(std::span<const std::int64_t> sorted, std::int64_t id) {
  return std::int32_t(std::lower_bound(sorted.begin(), sorted.end(), id) - sorted.begin());
}

} // namespace

LevelSynthesizer::LevelSynthesizer(const par::Comm& comm, LevelStencils stencils,
                                   std::span<const std::int64_t> rank_offsets,
                                   std::span<const std::int64_t> coarser_offsets,
                                   const std::vector<img::RgbImage>& pyramid, int level,
                                   const NeighbourhoodTemplate& layout, SearchMethod method,
                                   ExemplarBorder border, std::uint64_t seed)
    : comm_(comm), stencils_(std::move(stencils)), rank_offsets_(rank_offsets),
      coarser_offsets_(coarser_offsets), image_(pyramid[std::size_t(level)]),
      current_mean_(mean_colour(pyramid[std::size_t(level)])),
      coarser_mean_(std::size_t(level) + 1 < pyramid.size()
                        ? mean_colour(pyramid[std::size_t(level) + 1])
                        : current_mean_) {
  TEXSIM_VERIFY(stencils_.coarser_count == 0 || !coarser_offsets.empty(),
                "coarser-part stencils without the coarser level's runs");
  // The mesh's coarser part exists only when the layout has one and the level has a coarser one.
  NeighbourhoodTemplate used = layout;
  if (stencils_.coarser_count == 0)
    used.coarser.clear();
  for (const Pass pass : {Pass::extrapolate, Pass::refine}) {
    if (used.samples(pass) == 0) {
      passes_.push_back(nullptr);
      continue;
    }
    auto data = std::make_unique<PassData>();
    data->pass = pass;
    // The classes read the stencils' level ids: before localise_stencils.
    data->order = synthesis_order(comm, stencils_, rank_offsets, seed, level, pass);
    data->exemplar = exemplar_neighbourhoods(pyramid, level, used, pass, border);
    if (method == SearchMethod::tsvq)
      data->exact = make_neighbourhood_search(SearchMethod::pruned, data->exemplar.table);
    data->search = make_neighbourhood_search(method, std::move(data->exemplar.table));
    passes_.push_back(std::move(data));
  }
  localise_stencils();
  find_readers();
}

LevelSynthesizer::~LevelSynthesizer() = default;

void LevelSynthesizer::localise_stencils() {
  const std::int64_t first = stencils_.first, owned = stencils_.owned;
  const auto is_owned = [&](std::int64_t v) { return v >= first && v < first + owned; };
  halo_ = sampled_vertices(stencils_.current, [&](std::int64_t v) { return !is_owned(v); });
  coarser_reads_ = sampled_vertices(stencils_.coarser, [](std::int64_t) { return true; });
  for (auto& sample : stencils_.current)
    if (sample.covered())
      for (auto& v : sample.vertices)
        v = is_owned(v) ? std::int32_t(v - first) : std::int32_t(owned) + index_in(halo_, v);
  for (auto& sample : stencils_.coarser)
    if (sample.covered())
      for (auto& v : sample.vertices)
        v = index_in(coarser_reads_, v);
}

void LevelSynthesizer::find_readers() {
  // Tell every owner which of its vertices this rank's stencils read.
  std::vector<std::vector<ReadRequest>> requests(std::size_t(comm_.size));
  for (const std::int64_t v : halo_)
    requests[std::size_t(par::owner_of(rank_offsets_, v))].push_back({v, comm_.rank});
  auto received = par::exchange_records(comm_, requests);
  std::sort(received.begin(), received.end(), [](const ReadRequest& a, const ReadRequest& b) {
    return std::tie(a.id, a.reader) < std::tie(b.id, b.reader);
  });
  reader_offsets_.assign(std::size_t(stencils_.owned) + 1, 0);
  for (const auto& r : received)
    ++reader_offsets_[std::size_t(r.id - stencils_.first) + 1];
  for (std::size_t i = 1; i < reader_offsets_.size(); ++i)
    reader_offsets_[i] += reader_offsets_[i - 1];
  for (const auto& r : received)
    readers_.push_back(r.reader);
}

bool LevelSynthesizer::runs(Pass pass) const {
  return passes_[pass == Pass::extrapolate ? 0 : 1] != nullptr;
}

const SynthesisOrder& LevelSynthesizer::order(Pass pass) const {
  const PassData* data = passes_[pass == Pass::extrapolate ? 0 : 1].get();
  TEXSIM_VERIFY(data, "order of a pass that reads nothing");
  return data->order;
}

void LevelSynthesizer::read_colours(const LevelColours& current, const LevelColours* coarser) {
  TEXSIM_VERIFY(std::int64_t(current.colours.size()) == stencils_.owned,
                current.colours.size() << " colours for a run of " << stencils_.owned);
  TEXSIM_VERIFY(coarser || coarser_offsets_.empty(), "coarser samples without the coarser colours");
  colours_ = par::fetch_from_owners(comm_, rank_offsets_, std::span<const std::int64_t>(halo_),
                                    std::span<const img::Rgb>(current.colours));
  colours_.insert(colours_.begin(), current.colours.begin(), current.colours.end());
  if (coarser)
    coarser_colours_ = par::fetch_from_owners(comm_, coarser_offsets_,
                                              std::span<const std::int64_t>(coarser_reads_),
                                              std::span<const img::Rgb>(coarser->colours));
}

void LevelSynthesizer::query(const PassData& data, std::int64_t local,
                             std::vector<double>& out) const {
  out.resize(std::size_t(data.search->dimension()));
  double* value = out.data();
  if (data.pass == Pass::refine)
    for (const auto& sample : stencils_.current_of(local)) {
      add_sample(sample, colours_, current_mean_, value);
      value += 3;
    }
  for (const auto& sample : stencils_.coarser_of(local)) {
    add_sample(sample, coarser_colours_, coarser_mean_, value);
    value += 3;
  }
  TEXSIM_ASSERT(value == out.data() + out.size(), "neighbourhood query of the wrong size");
}

void LevelSynthesizer::run_pass(Pass pass, std::int32_t first_class, LevelColours& current,
                                const std::function<void(std::int32_t)>& after_class) {
  const PassData* data = passes_[pass == Pass::extrapolate ? 0 : 1].get();
  TEXSIM_VERIFY(data, "run_pass on a pass that reads nothing");
  TEXSIM_VERIFY(colours_.size() == std::size_t(stencils_.owned) + halo_.size(),
                "run_pass before read_colours");
  for (std::int32_t c = first_class; c < data->order.classes; ++c) {
    const auto& members = data->order.owned_members[std::size_t(c)];
    // Queries go to the search in batches: the exhaustive scan reads the table once per batch.
    const auto chunks = (members.size() + kBatch - 1) / kBatch;
#pragma omp parallel
    {
      std::vector<double> q, batch;
      std::int64_t rows[kBatch];
#pragma omp for schedule(dynamic, 2)
      for (std::size_t chunk = 0; chunk < chunks; ++chunk) {
        const std::size_t begin = chunk * kBatch;
        const std::size_t count = std::min(kBatch, members.size() - begin);
        batch.clear();
        for (std::size_t m = begin; m < begin + count; ++m) {
          query(*data, members[m], q);
          batch.insert(batch.end(), q.begin(), q.end());
        }
        data->search->nearest_batch(batch, {rows, count});
        for (std::size_t m = 0; m < count; ++m) {
          const std::int32_t pixel = data->exemplar.pixels[std::size_t(rows[m])];
          const auto local = std::size_t(members[begin + m]);
          current.pixels[local] = pixel;
          current.colours[local] = colours_[local] = image_.data()[std::size_t(pixel)];
        }
      }
    }
    send_class(members);
    after_class(c);
  }
}

void LevelSynthesizer::send_class(const std::vector<std::int64_t>& members) {
  std::vector<std::vector<ColourUpdate>> outgoing(std::size_t(comm_.size));
  for (const std::int64_t local : members) {
    const img::Rgb& c = colours_[std::size_t(local)];
    for (auto k = reader_offsets_[std::size_t(local)]; k < reader_offsets_[std::size_t(local) + 1];
         ++k)
      outgoing[std::size_t(readers_[std::size_t(k)])].push_back(
          {stencils_.first + local, {c.r, c.g, c.b}});
  }
  const auto owned = std::size_t(stencils_.owned);
  for (const auto& update : par::exchange_records(comm_, outgoing))
    colours_[owned + std::size_t(index_in(halo_, update.id))] = {update.rgb[0], update.rgb[1],
                                                                 update.rgb[2]};
}

double LevelSynthesizer::neighbourhood_error() const {
  const PassData* data = passes_[1] ? passes_[1].get() : passes_[0].get();
  double sums[2] = {0, 0}; // distance sum, vertex count
  if (data) {
    const NeighbourhoodSearch& exact = data->exact ? *data->exact : *data->search;
    const auto& table = exact.table();
    std::vector<double> q;
    const auto covered = [](std::span<const SampleWeights> samples) {
      return std::all_of(samples.begin(), samples.end(),
                         [](const SampleWeights& s) { return s.covered(); });
    };
    for (std::int64_t local = 0; local < stencils_.owned; ++local) {
      if (!covered(stencils_.current_of(local)) || !covered(stencils_.coarser_of(local)))
        continue; // samples standing in with the exemplar mean are not texture
      query(*data, local, q);
      sums[0] += std::sqrt(exact.distance2(exact.nearest(q), q));
      sums[1] += 1;
    }
    // Spread of the exemplar neighbourhoods: RMS distance to their mean (same on every rank).
    const std::int64_t rows = table.rows();
    std::vector<double> mean(std::size_t(table.dimension), 0.0);
    for (std::int64_t r = 0; r < rows; ++r)
      for (int k = 0; k < table.dimension; ++k)
        mean[std::size_t(k)] += table.values[std::size_t(r * table.dimension + k)];
    for (double& m : mean)
      m /= double(rows);
    double spread2 = 0;
    for (std::int64_t r = 0; r < rows; ++r)
      spread2 += exact.distance2(r, mean);
    const double spread = std::sqrt(spread2 / double(rows));
    MPI_Allreduce(MPI_IN_PLACE, sums, 2, MPI_DOUBLE, MPI_SUM, comm_.raw);
    return spread > 0 && sums[1] > 0 ? sums[0] / sums[1] / spread : 0.0;
  }
  return 0.0;
}

void LevelSynthesizer::neighbourhood(Pass pass, std::int64_t local,
                                     std::vector<double>& out) const {
  const PassData* data = passes_[pass == Pass::extrapolate ? 0 : 1].get();
  TEXSIM_VERIFY(data, "neighbourhood of a pass that reads nothing");
  query(*data, local, out);
}

const NeighbourhoodSearch& LevelSynthesizer::search(Pass pass) const {
  const PassData* data = passes_[pass == Pass::extrapolate ? 0 : 1].get();
  TEXSIM_VERIFY(data, "search of a pass that reads nothing");
  return *data->search;
}

std::size_t LevelSynthesizer::memory_bytes() const {
  std::size_t bytes = 0;
  for (const auto& data : passes_)
    if (data)
      bytes += data->search->memory_bytes() + (data->exact ? data->exact->memory_bytes() : 0);
  return bytes;
}

} // namespace texsim::pipelines::surface_synthesis
