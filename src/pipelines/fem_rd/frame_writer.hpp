#pragma once
/// One ParaView frame of an fem_rd run: the (possibly moved) surface with every species, written
/// as a .pvtu with one piece per rank (the rank's owned triangles).
#include "geom/distributed_mesh.hpp"
#include "pipelines/fem_rd/reaction_diffusion_solver.hpp"

#include <filesystem>
#include <string>

namespace texsim::pipelines::fem_rd {

/// Writes <dir>/<basename>.pvtu and its pieces; returns the .pvtu path. Collective.
std::filesystem::path write_frame(const par::Comm& comm, const geom::DistributedMesh& mesh,
                                  const ReactionDiffusionSolver& solver,
                                  const std::filesystem::path& dir, const std::string& basename);

} // namespace texsim::pipelines::fem_rd
