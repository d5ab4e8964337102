#pragma once
/// mesh_prep: turns a user's surface (or a generated one) into the clean, refined mesh the surface
/// pipelines need, and shows it in ParaView partitioned as a parallel run would split it.
///
/// Stages: load (read, then the documented repairs of geom::repair(), or generate), refine (Loop
/// subdivision), perturb (seeded noise along normals), measure (area, Euler characteristic, genus,
/// edge lengths), write (one .pvtp with a piece per rank: normals, vertex areas, owning rank; plus
/// a .pvd). Every rank builds the whole mesh (meshes here are small next to what the solvers do
/// with them); each rank writes the triangles of its Morton-curve part.
#include "pipelines/mesh_prep/mesh_prep_settings.hpp"
#include "pipelines/pipeline.hpp"

namespace texsim::pipelines::mesh_prep {

class MeshPrepPipeline : public Pipeline {
public:
  void configure(const ConfigSection& section) override;
  void run(RunContext& ctx) override;

private:
  MeshPrepSettings settings_;
};

} // namespace texsim::pipelines::mesh_prep
