#pragma once
/// summary.json: what a run did, how long each stage took, its metrics and output files.
#include "core/run_report.hpp"
#include "core/stage_timers.hpp"

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

namespace texsim::app {

struct SummaryHeader {
  std::string pipeline;
  int ranks = 1;
  int threads = 1;
  double wall_s = 0;
  std::string config_hash;
  bool restarted = false;
  /// Peak resident memory of each rank (getrusage), for the memory-per-rank figures.
  std::vector<std::int64_t> peak_resident_bytes;
  /// Each rank's largest proportional set size (PSS) seen at a stage end or at the end: memory
  /// that the ranks of a node share (node-shared exemplar data, libraries) counts once per node.
  std::vector<std::int64_t> proportional_bytes;
};

/// Writes <output_dir>/summary.json atomically (core/atomic_output.hpp). Rank 0 only.
void write_summary(const std::filesystem::path& output_dir, const SummaryHeader& header,
                   const StageTimers& timers, const RunReport& report);

} // namespace texsim::app
