#include "pipelines/turk_rd/stripe_direction.hpp"

#include "par/ghosted_vector.hpp"
#include "par/reproducible_sum.hpp"

#include <Eigen/Eigenvalues>

#include <vector>

namespace texsim::pipelines::turk_rd {

double stripes_across_axis(const par::Comm& comm, const geom::SurfaceCells& cells,
                           std::span<const double> owned_values, const geom::Vec3& axis) {
  const std::int32_t owned = cells.owned_count();
  par::GhostedVector halo(comm, owned, cells.ghost_blocks());
  halo.set_owned(owned_values);
  const std::span<const double> values = halo.local();
  const auto position = [&](std::int32_t local) {
    return local < owned ? cells.points()[local].position : cells.ghost_positions()[local - owned];
  };
  const geom::Vec3 unit_axis = axis.normalized();
  std::vector<double> along(std::size_t(owned), 0.0), total(std::size_t(owned), 0.0);
  for (std::int32_t i = 0; i < owned; ++i) {
    Eigen::Matrix3d spread = Eigen::Matrix3d::Zero();
    Eigen::Vector3d rhs = Eigen::Vector3d::Zero();
    for (const std::int32_t j : cells.neighbors().row(i)) {
      const geom::Vec3 d = position(j) - position(i);
      spread += d * d.transpose();
      rhs += d * (values[j] - values[i]);
    }
    // The tangent plane: the two directions the neighbours spread along most.
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> solver(spread);
    if (solver.eigenvalues()[1] <= 0)
      continue;
    geom::Vec3 gradient = geom::Vec3::Zero();
    for (int k = 1; k < 3; ++k)
      gradient += solver.eigenvectors().col(k).dot(rhs) / solver.eigenvalues()[k] *
                  solver.eigenvectors().col(k);
    const geom::Vec3 normal = solver.eigenvectors().col(0);
    const geom::Vec3 tangent_axis = unit_axis - unit_axis.dot(normal) * normal;
    if (tangent_axis.norm() < 0.1)
      continue;
    const double area = cells.areas()[i];
    const double projected = gradient.dot(tangent_axis);
    along[std::size_t(i)] = area * projected * projected;
    total[std::size_t(i)] = area * gradient.squaredNorm() * tangent_axis.squaredNorm();
  }
  const double sum_total = par::reproducible_sum(comm, total);
  return sum_total > 0 ? par::reproducible_sum(comm, along) / sum_total : 0.0;
}

} // namespace texsim::pipelines::turk_rd
