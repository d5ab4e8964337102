#include "pipelines/fem_rd/diffusion_field.hpp"

#include "core/error.hpp"
#include "geom/mesh_fields.hpp"
#include "geom/mesh_measures.hpp"

#include <Eigen/Core>
#include <mpi.h>

#include <algorithm>
#include <cmath>

namespace texsim::pipelines::fem_rd {
namespace {

constexpr const char* kSection = "fem_rd.diffusion";

/// A direction whose tangent part is below this fraction of its length has no tangent direction.
constexpr double kNormalFieldTolerance = 1e-6;

} // namespace

std::optional<DiffusionFieldSettings> read_diffusion_field(const ConfigSection& fem_rd,
                                                           const geom::MeshSource& mesh) {
  auto mesh_fields = geom::read_mesh_fields(fem_rd, mesh);
  if (!fem_rd.has("diffusion")) {
    if (!mesh_fields.empty())
      fem_rd.fail("mesh_fields", "a fem_rd.diffusion section to read them (its direction and "
                                 "scale are the only formulas that may)");
    return std::nullopt;
  }
  const ConfigSection section = fem_rd.section("diffusion");
  DiffusionFieldSettings settings;
  const auto direction = section.get<std::vector<std::string>>("direction", {"0", "0", "0"});
  if (direction.size() != 3)
    section.fail("direction", "3 expressions of x, y, z (the field's components)");
  std::copy(direction.begin(), direction.end(), settings.direction.begin());
  settings.along = section.get<double>("along", settings.along, positive());
  settings.across = section.get<double>("across", settings.across, positive());
  settings.scale = section.get<std::string>("scale", settings.scale);
  settings.species = section.get<std::vector<std::string>>("species", {});
  settings.mesh_fields = std::move(mesh_fields);
  return settings;
}

DiffusionField::DiffusionField(const DiffusionFieldSettings& settings,
                               const std::vector<std::string>& species)
    : settings_(settings) {
  for (const auto& name : settings.species)
    if (std::find(species.begin(), species.end(), name) == species.end()) {
      std::string known;
      for (const auto& s : species)
        known += (known.empty() ? "" : ", ") + s;
      TEXSIM_INPUT_ERROR(kSection << ".species: the model has no species '" << name
                                  << "', expected some of " << known);
    }
  for (const auto& name : settings.mesh_fields)
    if (std::find(species.begin(), species.end(), name) != species.end())
      TEXSIM_INPUT_ERROR("fem_rd.mesh_fields: '" << name
                                                 << "' is also a species' name; expected names "
                                                    "that say which one a formula reads");
  for (std::size_t c = 0; c < 3; ++c)
    direction_[c] = std::make_unique<geom::PointExpression>(
        settings.direction[c], settings.mesh_fields,
        std::string(kSection) + ".direction[" + std::to_string(c) + "]");
  std::vector<std::string> scale_names = species;
  scale_names.insert(scale_names.end(), settings.mesh_fields.begin(), settings.mesh_fields.end());
  scale_ = std::make_unique<geom::PointExpression>(settings.scale, scale_names,
                                                   std::string(kSection) + ".scale");
  depends_on_species_ = std::any_of(species.begin(), species.end(),
                                    [&](const std::string& name) { return scale_->uses(name); });
}

bool DiffusionField::applies_to(const std::string& name) const {
  return settings_.species.empty() || std::find(settings_.species.begin(), settings_.species.end(),
                                                name) != settings_.species.end();
}

namespace {
std::vector<double> coordinates(const geom::TriangleMesh& mesh) {
  std::vector<double> xyz;
  xyz.reserve(3 * mesh.positions.size());
  for (const auto& p : mesh.positions)
    xyz.insert(xyz.end(), {p.x(), p.y(), p.z()});
  return xyz;
}

/// The first `count` values of each column.
std::vector<std::span<const double>> first(const std::vector<std::vector<double>>& columns,
                                           std::size_t count) {
  std::vector<std::span<const double>> spans;
  for (const auto& column : columns)
    spans.push_back(std::span(column).first(count));
  return spans;
}
} // namespace

void DiffusionField::update_mesh_fields(const geom::TriangleMesh& mesh) const {
  if (settings_.mesh_fields.empty())
    return;
  TEXSIM_VERIFY(settings_.mesh_field_values,
                "fem_rd.mesh_fields were not loaded before the diffusion field was evaluated");
  const auto& fields = *settings_.mesh_field_values;
  int moved = mesh.positions != sampled_positions_ ? 1 : 0, any_moved = 0;
  MPI_Allreduce(&moved, &any_moved, 1, MPI_INT, MPI_MAX, fields.comm().raw);
  if (!any_moved)
    return;
  sampled_values_ = fields.sample(mesh.positions);
  sampled_positions_ = mesh.positions;
}

const std::vector<std::vector<double>>&
DiffusionField::mesh_fields_at(const geom::TriangleMesh& mesh) const {
  TEXSIM_VERIFY(settings_.mesh_fields.empty() || mesh.positions == sampled_positions_,
                "fem_rd.mesh_fields were not sampled at these positions (update_mesh_fields)");
  return sampled_values_;
}

std::vector<geom::Vec3> DiffusionField::tangent_directions(const geom::TriangleMesh& mesh) const {
  const std::vector<double> xyz = coordinates(mesh);
  const auto mesh_fields = first(mesh_fields_at(mesh), mesh.positions.size());
  std::array<std::vector<double>, 3> field;
  for (std::size_t c = 0; c < 3; ++c)
    field[c] = direction_[c]->evaluate(xyz, mesh_fields);
  const auto normals = geom::vertex_normals(mesh);
  std::vector<geom::Vec3> directions(mesh.positions.size(), geom::Vec3::Zero());
  for (std::size_t i = 0; i < directions.size(); ++i) {
    const geom::Vec3 f(field[0][i], field[1][i], field[2][i]);
    const geom::Vec3 tangent = f - f.dot(normals[i]) * normals[i];
    if (tangent.norm() > kNormalFieldTolerance * f.norm() && tangent.norm() > 0)
      directions[i] = tangent.normalized();
  }
  return directions;
}

std::vector<double>
DiffusionField::tensors(const geom::TriangleMesh& mesh, std::size_t count,
                        const std::vector<std::span<const double>>& species) const {
  std::vector<double> xyz = coordinates(mesh);
  xyz.resize(3 * count);
  std::vector<std::span<const double>> columns = species;
  for (const auto column : first(mesh_fields_at(mesh), count))
    columns.push_back(column);
  const std::vector<double> scale = scale_->evaluate(xyz, columns);
  const auto directions = tangent_directions(mesh);
  std::vector<double> tensors(9 * directions.size(), 0.0);
  for (std::size_t i = 0; i < count; ++i) {
    if (!(std::isfinite(scale[i]) && scale[i] > 0))
      TEXSIM_INPUT_ERROR(kSection << ".scale: expected a positive rate factor everywhere, got "
                                  << scale[i] << " at (" << xyz[3 * i] << ", " << xyz[3 * i + 1]
                                  << ", " << xyz[3 * i + 2] << ")");
    const geom::Vec3& t = directions[i];
    const Eigen::Matrix3d d =
        t.isZero() ? Eigen::Matrix3d(0.5 * (settings_.along + settings_.across) *
                                     Eigen::Matrix3d::Identity())
                   : Eigen::Matrix3d(settings_.across * Eigen::Matrix3d::Identity() +
                                     (settings_.along - settings_.across) * t * t.transpose());
    for (int k = 0; k < 9; ++k)
      tensors[9 * i + std::size_t(k)] = scale[i] * d(k / 3, k % 3);
  }
  return tensors;
}

} // namespace texsim::pipelines::fem_rd
