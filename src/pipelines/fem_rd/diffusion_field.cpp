#include "pipelines/fem_rd/diffusion_field.hpp"

#include "core/error.hpp"
#include "geom/mesh_measures.hpp"

#include <Eigen/Core>

#include <algorithm>
#include <cmath>

namespace texsim::pipelines::fem_rd {
namespace {

constexpr const char* kSection = "fem_rd.diffusion";

/// A direction whose tangent part is below this fraction of its length has no tangent direction.
constexpr double kNormalFieldTolerance = 1e-6;

} // namespace

std::optional<DiffusionFieldSettings> read_diffusion_field(const ConfigSection& fem_rd) {
  if (!fem_rd.has("diffusion"))
    return std::nullopt;
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
  for (std::size_t c = 0; c < 3; ++c)
    direction_[c] = std::make_unique<geom::PointExpression>(
        settings.direction[c], std::vector<std::string>{},
        std::string(kSection) + ".direction[" + std::to_string(c) + "]");
  scale_ = std::make_unique<geom::PointExpression>(settings.scale, species,
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
} // namespace

std::vector<geom::Vec3> DiffusionField::tangent_directions(const geom::TriangleMesh& mesh) const {
  const std::vector<double> xyz = coordinates(mesh);
  std::array<std::vector<double>, 3> field;
  for (std::size_t c = 0; c < 3; ++c)
    field[c] = direction_[c]->evaluate(xyz, {});
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
  const std::vector<double> scale = scale_->evaluate(xyz, species);
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
