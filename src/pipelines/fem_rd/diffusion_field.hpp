#pragma once
/// Diffusion that varies over the surface and with direction (fem_rd.diffusion): the constant
/// rate C0C1 of a species in eq. (2) becomes the tensor
///     D(x) = C0C1 * scale(x) * (across * I + (along - across) t t^T),
/// where t is a user direction field projected onto the tangent plane at x and normalised:
/// patterns stretch along t where along > across (the pattern of isotropic diffusion seen in
/// coordinates squeezed by sqrt(along / across) along t), so stripes follow t. `scale` makes
/// the rate vary with position and, when it reads a species' name, with the pattern. Where the
/// field is normal to the surface (or zero) t is undefined and the tensor is isotropic with the
/// mean rate (along + across) / 2.
///
/// Direction and scale may read point arrays of the mesh file (fem_rd.mesh_fields), taken at the
/// closest point of the file's surface, as turk_rd's diffusion_scale does.
///
/// A tensor of the geometry only is assembled into K once per mesh rebuild; one that reads the
/// species is assembled every step from u^n (ReactionDiffusionSolver).
#include "core/config.hpp"
#include "geom/distributed_mesh_fields.hpp"
#include "geom/mesh_source.hpp"
#include "geom/point_expression.hpp"
#include "geom/triangle_mesh.hpp"

#include <array>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

namespace texsim::pipelines::fem_rd {

struct DiffusionFieldSettings {
  std::array<std::string, 3> direction{"0", "0", "0"}; ///< fem_rd.diffusion.direction
  double along = 1.0;                                  ///< fem_rd.diffusion.along
  double across = 1.0;                                 ///< fem_rd.diffusion.across
  std::string scale = "1";                             ///< fem_rd.diffusion.scale
  std::vector<std::string> species;                    ///< empty: every species
  /// fem_rd.mesh_fields: point arrays of fem_rd.mesh.file that direction and scale may read.
  std::vector<std::string> mesh_fields{};
  /// Their values (field k of mesh_fields), loaded by the pipeline before the solver is built (the
  /// file on rank 0, sampled for every rank's vertices); may stay empty while only the formulas
  /// are checked.
  std::shared_ptr<const geom::DistributedMeshFields> mesh_field_values{};
};

/// The section fem_rd.diffusion with fem_rd.mesh_fields, or nothing when it is absent. InputError
/// naming the key for a direction that is not 3 expressions, rates that are not positive, or mesh
/// fields without a diffusion section (nothing else reads them).
std::optional<DiffusionFieldSettings> read_diffusion_field(const ConfigSection& fem_rd,
                                                           const geom::MeshSource& mesh);

class DiffusionField {
public:
  /// The field of a model whose species are `species` (the scale may read their values; direction
  /// and scale may read the mesh fields). InputError naming the key for an unparsable formula, a
  /// listed species the model lacks or a mesh field named like a species.
  DiffusionField(const DiffusionFieldSettings& settings, const std::vector<std::string>& species);

  /// Whether the tensor applies to species `name`.
  bool applies_to(const std::string& name) const;
  /// Whether the scale reads a species' values: then the tensors change every step.
  bool depends_on_species() const { return depends_on_species_; }

  /// Samples fem_rd.mesh_fields at `mesh`'s vertices when they moved on some rank since the last
  /// call; tangent_directions() and tensors() read those values. Collective (a no-op without
  /// mesh fields).
  void update_mesh_fields(const geom::TriangleMesh& mesh) const;

  /// The unit direction t at every vertex of `mesh`: the field projected onto the tangent plane
  /// (the vertex normal's), zero where that leaves nothing.
  std::vector<geom::Vec3> tangent_directions(const geom::TriangleMesh& mesh) const;
  /// D(x) / C0C1 at the first `count` vertices of `mesh` (9 values each, row-major; zeros for
  /// the vertices after them), `species[k]` the values of species k there. InputError naming
  /// fem_rd.diffusion.scale where the scale is not positive and finite.
  std::vector<double> tensors(const geom::TriangleMesh& mesh, std::size_t count,
                              const std::vector<std::span<const double>>& species) const;

private:
  /// The mesh fields at every vertex of `mesh`, as update_mesh_fields sampled them.
  const std::vector<std::vector<double>>& mesh_fields_at(const geom::TriangleMesh& mesh) const;

  DiffusionFieldSettings settings_;
  mutable std::vector<geom::Vec3> sampled_positions_;
  mutable std::vector<std::vector<double>> sampled_values_;
  bool depends_on_species_ = false;
  std::array<std::unique_ptr<geom::PointExpression>, 3> direction_;
  std::unique_ptr<geom::PointExpression> scale_;
};

} // namespace texsim::pipelines::fem_rd
