#include "pipelines/solid_synthesis/anisometric_field.hpp"

#include "vol/trilinear.hpp"

#include "core/error.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <utility>

namespace texsim::pipelines::solid_synthesis {
namespace {

constexpr double kDegree = std::numbers::pi / 180.0;

Eigen::Matrix3d rotation_about_z(double radians) {
  return Eigen::AngleAxisd(radians, Eigen::Vector3d::UnitZ()).toRotationMatrix();
}

class IdentityField final : public AxesField {
public:
  Eigen::Matrix3d axes(const Eigen::Vector3d&) const override {
    return Eigen::Matrix3d::Identity();
  }
};

class EllipseField final : public AxesField {
public:
  explicit EllipseField(double ratio) : inverse_ratio_squared_(1.0 / (ratio * ratio)) {}

  Eigen::Matrix3d axes(const Eigen::Vector3d& p) const override {
    // The ellipses are the level sets of (dx / ratio)^2 + dy^2; their gradient is the outward
    // normal and the tangent is that normal turned by +90 degrees.
    const double dx = p.x() - 0.5, dy = p.y() - 0.5;
    const double gx = dx * inverse_ratio_squared_, gy = dy;
    if (gx == 0.0 && gy == 0.0) {
      return Eigen::Matrix3d::Identity();
    }
    return rotation_about_z(std::atan2(gx, -gy));
  }

private:
  double inverse_ratio_squared_;
};

class RotationField final : public AxesField {
public:
  RotationField(const Eigen::Vector3d& axis, double angle_degrees)
      : rotation_(Eigen::AngleAxisd(angle_degrees * kDegree, axis.normalized())) {}

  Eigen::Matrix3d axes(const Eigen::Vector3d&) const override { return rotation_; }

private:
  Eigen::Matrix3d rotation_;
};

class ZigzagField final : public AxesField {
public:
  ZigzagField(double angle_degrees, int bands) : angle_(angle_degrees * kDegree), bands_(bands) {}

  Eigen::Matrix3d axes(const Eigen::Vector3d& p) const override {
    constexpr double kSharpness = 3.0;
    const double wave = std::sin(std::numbers::pi * bands_ * p.y());
    return rotation_about_z(angle_ * std::tanh(kSharpness * wave) / std::tanh(kSharpness));
  }

private:
  double angle_;
  int bands_;
};

class VectorGridField final : public AxesField {
public:
  explicit VectorGridField(vol::RgbGrid vectors) : vectors_(std::move(vectors)) {}

  Eigen::Matrix3d axes(const Eigen::Vector3d& p) const override {
    // Voxel centres at (i + 1/2) / n of the unit cube.
    const vol::Dims dims = vectors_.dims();
    const int n[3] = {dims.nx, dims.ny, dims.nz};
    std::array<double, 3> at{};
    for (int a = 0; a < 3; ++a)
      at[std::size_t(a)] = p[a] * n[a] - 0.5;
    const auto v = vol::trilinear(vectors_, at);
    return frame_from_x_axis(Eigen::Vector3d(v[0], v[1], v[2]));
  }

private:
  vol::RgbGrid vectors_;
};

} // namespace

std::size_t LevelJacobians::index(int i, int j, int k) const {
  TEXSIM_ASSERT(i >= 0 && i < level_size && j >= 0 && j < level_size && k >= z_begin && k < z_end,
                "voxel (" << i << ", " << j << ", " << k << ") outside the sampled planes ["
                          << z_begin << ", " << z_end << ") of level " << level_size);
  const auto n = static_cast<std::size_t>(level_size);
  return static_cast<std::size_t>(i) +
         n * (static_cast<std::size_t>(j) + n * static_cast<std::size_t>(k - z_begin));
}

Eigen::Matrix3d frame_from_x_axis(const Eigen::Vector3d& x_axis) {
  const double length = x_axis.norm();
  if (length == 0.0) {
    return Eigen::Matrix3d::Identity();
  }
  const Eigen::Vector3d x = x_axis / length;
  Eigen::Matrix3d frame;
  frame.col(0) = x_axis;
  constexpr double kParallel = 1.0 - 1e-12;
  if (std::abs(x.z()) < kParallel) {
    const Eigen::Vector3d z = (Eigen::Vector3d::UnitZ() - x.z() * x).normalized();
    frame.col(1) = z.cross(x);
    frame.col(2) = z;
  } else {
    const Eigen::Vector3d y = (Eigen::Vector3d::UnitY() - x.y() * x).normalized();
    frame.col(1) = y;
    frame.col(2) = x.cross(y);
  }
  return frame;
}

LevelJacobians sample_level(const AxesField& field, int level_size, int z_begin, int z_end,
                            int finest_size) {
  TEXSIM_VERIFY(level_size > 0 && finest_size >= level_size && finest_size % level_size == 0,
                "level size " << level_size << " must divide the finest size " << finest_size);
  TEXSIM_VERIFY(z_begin <= z_end, "empty plane range [" << z_begin << ", " << z_end << ")");
  const int samples = std::min(4, finest_size / level_size);
  const double voxel = 1.0 / level_size;
  const double weight = 1.0 / (samples * samples * samples);

  LevelJacobians level;
  level.level_size = level_size;
  level.z_begin = z_begin;
  level.z_end = z_end;
  const std::size_t plane = static_cast<std::size_t>(level_size) * level_size;
  const std::size_t count = plane * static_cast<std::size_t>(z_end - z_begin);
  level.jacobian.resize(count);
  level.inverse.resize(count);

  // Sub-cell centre offsets inside a voxel, in unit coordinates.
  std::vector<double> offsets(samples);
  for (int s = 0; s < samples; ++s) {
    offsets[s] = (s + 0.5) / samples * voxel;
  }

#pragma omp parallel for schedule(static)
  for (int k = z_begin; k < z_end; ++k) {
    const int wrapped_k = ((k % level_size) + level_size) % level_size;
    for (int j = 0; j < level_size; ++j) {
      for (int i = 0; i < level_size; ++i) {
        const Eigen::Vector3d corner(i * voxel, j * voxel, wrapped_k * voxel);
        Eigen::Matrix3d sum = Eigen::Matrix3d::Zero();
        for (const double oz : offsets) {
          for (const double oy : offsets) {
            for (const double ox : offsets) {
              sum += field.axes(corner + Eigen::Vector3d(ox, oy, oz));
            }
          }
        }
        Eigen::Matrix3d average = sum * weight;
        if (!(std::abs(average.determinant()) >= kSingularFrameDeterminant)) { // NaN too
          average.setIdentity();
        }
        const std::size_t at = static_cast<std::size_t>(i) +
                               level_size * static_cast<std::size_t>(j) +
                               plane * static_cast<std::size_t>(k - z_begin);
        level.inverse[at] = average.cast<float>();
        level.jacobian[at] = average.inverse().cast<float>();
      }
    }
  }
  return level;
}

std::unique_ptr<AxesField> identity_field() {
  return std::make_unique<IdentityField>();
}

std::unique_ptr<AxesField> ellipse_field(double ratio) {
  TEXSIM_VERIFY(ratio > 0.0, "ellipse axis ratio must be positive, got " << ratio);
  return std::make_unique<EllipseField>(ratio);
}

std::unique_ptr<AxesField> rotation_field(const Eigen::Vector3d& axis, double angle_degrees) {
  TEXSIM_VERIFY(axis.norm() > 0.0, "rotation axis must not be zero");
  return std::make_unique<RotationField>(axis, angle_degrees);
}

std::unique_ptr<AxesField> zigzag_field(double angle_degrees, int bands) {
  TEXSIM_VERIFY(bands > 0, "zigzag band count must be positive, got " << bands);
  return std::make_unique<ZigzagField>(angle_degrees, bands);
}

std::unique_ptr<AxesField> vector_grid_field(vol::RgbGrid vectors) {
  TEXSIM_VERIFY(vectors.size() > 0, "vector grid field needs a non-empty grid");
  return std::make_unique<VectorGridField>(std::move(vectors));
}

} // namespace texsim::pipelines::solid_synthesis
