#pragma once
/// Saving and restoring the state of an fem_rd run: every species, the surface positions and the
/// positions the RD matrices were last built on, keyed by the input mesh's vertex ids so that a
/// checkpoint written at one rank count restarts at any other.
#include "geom/distributed_mesh.hpp"
#include "io/checkpoint_store.hpp"
#include "pipelines/fem_rd/reaction_diffusion_solver.hpp"

#include <string>
#include <vector>

namespace texsim::pipelines::fem_rd {

struct GeometryState {
  std::vector<geom::Vec3> positions;        ///< current surface, local mesh order (owned + halo)
  std::vector<geom::Vec3> matrix_positions; ///< surface the RD matrices were built on
};

/// Per-vertex values a run keeps besides the species (e.g. locked_phase's sums): one dataset
/// each, an array over the owned vertices.
struct ExtraColumn {
  std::string dataset;
  std::vector<double>* owned;
};

/// Writes checkpoint `step` (the state after `step` steps), with the extra columns. Collective.
void save_state(const io::CheckpointStore& store, std::int64_t step,
                const geom::DistributedMesh& mesh, const ReactionDiffusionSolver& solver,
                const GeometryState& geometry, const std::vector<ExtraColumn>& extra = {});

/// Restores species values into `solver` and the extra columns, and returns the step and the
/// geometry. Each rank reads an even share of the rows and sends each row, through the rank that
/// the row's input id maps to, on to the rank that owns the vertex: no rank holds the whole
/// state. Throws InputError naming the file if its species, extra columns, vertex count or
/// vertex ids do not match this run. Collective.
std::int64_t load_state(const io::CheckpointReader& reader, const geom::DistributedMesh& mesh,
                        ReactionDiffusionSolver& solver, GeometryState& geometry,
                        const std::vector<ExtraColumn>& extra = {});

} // namespace texsim::pipelines::fem_rd
