#include "pipelines/solid_synthesis/solid_synthesis_settings.hpp"

#include <algorithm>
#include <cmath>
#include <string>

namespace texsim::pipelines::solid_synthesis {
namespace {

constexpr int kMaxEdge = 4096;

std::array<int, 3> read_dims(const ConfigSection& synthesis) {
  const int edge = synthesis.get<int>("size", 128, int_in_range(2, kMaxEdge));
  if (!synthesis.has("dims"))
    return {edge, edge, edge};
  const auto dims = synthesis.require<std::array<double, 3>>("dims");
  std::array<int, 3> out{};
  for (int a = 0; a < 3; ++a) {
    if (dims[a] != std::floor(dims[a]) || dims[a] < 2 || dims[a] > kMaxEdge)
      synthesis.fail("dims", "three integers in [2, " + std::to_string(kMaxEdge) + "]");
    out[a] = static_cast<int>(dims[a]);
  }
  return out;
}

int levels_for(const std::array<int, 3>& dims) {
  const int edge = *std::max_element(dims.begin(), dims.end());
  int levels = 0;
  while ((1 << levels) < edge)
    ++levels;
  return levels;
}

} // namespace

SolidSynthesisSettings read_solid_synthesis_settings(const ConfigSection& section) {
  SolidSynthesisSettings settings;
  settings.mode = section.choice<RunMode>(
      "mode", settings.mode,
      {{"synthesis", RunMode::synthesis}, {"similarity_sets", RunMode::similarity_sets}});
  settings.exemplar = read_exemplar_settings(section.section("exemplar"));

  const auto appearance = section.section("appearance");
  settings.appearance.dimensions =
      appearance.get<int>("dimensions", settings.appearance.dimensions, int_in_range(1, 64));
  settings.appearance.window =
      appearance.get<int>("window", settings.appearance.window, int_in_range(1, 9));
  if (settings.appearance.window % 2 == 0)
    appearance.fail("window", "an odd integer (the neighbourhood is centred on the voxel)");
  settings.appearance.border = settings.exemplar.border;

  const auto similarity = section.section("similarity");
  settings.similarity.k = similarity.get<int>("k", settings.similarity.k, int_in_range(1, 16));
  settings.similarity.window =
      similarity.get<int>("window", settings.similarity.window, int_in_range(1, 31));
  if (settings.similarity.window % 2 == 0)
    similarity.fail("window", "an odd integer (the exclusion window is centred on a candidate)");
  settings.similarity.periodic = settings.exemplar.border == ExemplarBorder::toroidal;
  settings.similarity.search =
      similarity.choice<ShortlistSearch>("search", settings.similarity.search,
                                         {{"auto", ShortlistSearch::automatic},
                                          {"tree", ShortlistSearch::tree},
                                          {"scan", ShortlistSearch::scan}});
  settings.cache_dir = similarity.get<std::string>("cache_dir", settings.cache_dir.string());

  const auto synthesis = section.section("synthesis");
  settings.dims = read_dims(synthesis);
  settings.synthesis.levels = levels_for(settings.dims);
  settings.synthesis.jitter =
      synthesis.get<double>("jitter", settings.synthesis.jitter, in_range(0.0, 4.0));
  settings.synthesis.finest_jitter =
      synthesis.get<double>("finest_jitter", settings.synthesis.finest_jitter, in_range(0.0, 4.0));
  settings.synthesis.correction_passes =
      synthesis.get<int>("passes", settings.synthesis.correction_passes, int_in_range(0, 16));
  if (synthesis.has("min_improvement"))
    settings.synthesis.min_improvement =
        synthesis.require<double>("min_improvement", in_range(0.0, 1.0));
  settings.synthesis.coherence =
      synthesis.get<double>("coherence", settings.synthesis.coherence, in_range(0.0, 100.0));
  settings.metric_stride = synthesis.get<int>("metric_stride", 0, non_negative_int());

  if (section.has("field"))
    settings.field = read_field_settings(section.section("field"));

  const int smallest = *std::min_element(settings.dims.begin(), settings.dims.end());
  const std::vector<double> positions =
      section.get<std::vector<double>>("cross_sections", {static_cast<double>(smallest / 2)});
  for (const double p : positions) {
    if (p != std::floor(p) || p < 0 || p >= smallest)
      section.fail("cross_sections", "voxel positions in [0, " + std::to_string(smallest - 1) +
                                         "] (applied to X, Y and Z)");
    settings.cross_sections.push_back(static_cast<int>(p));
  }
  settings.vdb_compression =
      section.choice<vol::VdbCompression>("vdb_compression", settings.vdb_compression,
                                          {{"blosc", vol::VdbCompression::blosc},
                                           {"zip", vol::VdbCompression::zip},
                                           {"none", vol::VdbCompression::none}});
  return settings;
}

} // namespace texsim::pipelines::solid_synthesis
