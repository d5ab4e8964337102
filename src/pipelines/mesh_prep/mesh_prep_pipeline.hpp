#pragma once
/// mesh_prep: turns a user's surface (or a generated one) into the clean, refined mesh the surface
/// pipelines need, and shows it in ParaView partitioned as a parallel run would split it.
///
/// Stages: build (read with the repairs of geom::repair that `input.repair` selects, or generate;
/// isotropic remeshing; Loop subdivision; seeded noise), measure (area, Euler characteristic,
/// genus, edge lengths, triangle quality: smallest angle, aspect-ratio histogram), write (one .pvtp
/// with a piece per rank: normals, vertex areas, owning rank; plus a .pvd). Every rank builds the
/// whole mesh; each rank writes the triangles of its Morton-curve part.
#include "geom/mesh_memory.hpp"
#include "geom/mesh_source.hpp"
#include "pipelines/pipeline.hpp"

namespace texsim::pipelines::mesh_prep {

class MeshPrepPipeline : public Pipeline {
public:
  /// Reads `mesh_prep.input` (see geom/mesh_source.hpp).
  void configure(const ConfigSection& section, const RunSettings& run) override;
  void run(RunContext& ctx) override;
  /// The whole mesh on every rank, with its CGAL subdivision and topology (measured: 466 MiB
  /// peak for 1.3 million triangles, estimated 500 MiB).
  MemoryEstimate estimate_memory(int ranks) const override {
    return geom::estimate_mesh_memory(source_, "mesh_prep.input", ranks, 400, 0);
  }
  /// mesh_prep writes no checkpoints: --restart would only overwrite the directory it names.
  bool restartable() const override { return false; }

private:
  geom::MeshSource source_;
};

} // namespace texsim::pipelines::mesh_prep
