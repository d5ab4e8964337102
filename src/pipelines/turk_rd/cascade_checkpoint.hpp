#pragma once
/// Saving and restoring a turk_rd run: which stage of the cascade is running and how far it got,
/// the running stage's species and the final values of the stages before it, keyed by cell id so
/// that a checkpoint written at one rank count restarts at any other.
#include "geom/surface_cells.hpp"
#include "io/checkpoint_store.hpp"

#include <map>
#include <string>
#include <vector>

namespace texsim::pipelines::turk_rd {

struct CascadeState {
  std::size_t stage = 0;       ///< index of the running stage
  std::int64_t stage_step = 0; ///< steps done in it
  /// "<stage>_<species>" of finished stages and "<species>" of the running one -> owned values.
  std::map<std::string, std::vector<double>> fields;
};

/// Writes checkpoint `step` (cumulative steps over all stages). Collective.
void save_cascade(const io::CheckpointStore& store, std::int64_t step,
                  const geom::SurfaceCells& cells, const CascadeState& state);

/// Reads the state; `expected_fields` are the names the run needs. Throws InputError naming the
/// file if the cell count or a field does not match. Collective.
CascadeState load_cascade(const io::CheckpointReader& reader, const geom::SurfaceCells& cells,
                          const std::vector<std::string>& expected_fields);

} // namespace texsim::pipelines::turk_rd
