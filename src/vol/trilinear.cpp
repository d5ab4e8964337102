#include "vol/trilinear.hpp"

#include <algorithm>

namespace texsim::vol {

std::array<double, 3> trilinear(const RgbGrid& grid, const std::array<double, 3>& at) {
  const Dims dims = grid.dims();
  const int n[3] = {dims.nx, dims.ny, dims.nz};
  int lower[3];
  double weight[3];
  for (int a = 0; a < 3; ++a) {
    const double u = std::clamp(at[std::size_t(a)], 0.0, double(n[a] - 1));
    lower[a] = std::min(int(u), n[a] - 1);
    weight[a] = u - lower[a];
  }
  std::array<double, 3> value{};
  for (int corner = 0; corner < 8; ++corner) {
    double w = 1.0;
    int index[3];
    for (int a = 0; a < 3; ++a) {
      const int up = (corner >> a) & 1;
      w *= up ? weight[a] : 1.0 - weight[a];
      index[a] = lower[a] + up;
    }
    if (w == 0.0)
      continue;
    const img::Rgb& c = grid.clamped(index[0], index[1], index[2]);
    value[0] += w * c.r;
    value[1] += w * c.g;
    value[2] += w * c.b;
  }
  return value;
}

std::array<double, 3> voxel_coordinates(const RgbGrid& grid, const std::array<double, 3>& world) {
  std::array<double, 3> at{};
  for (std::size_t a = 0; a < 3; ++a)
    at[a] = (world[a] - grid.origin()[a]) / grid.spacing()[a];
  return at;
}

} // namespace texsim::vol
