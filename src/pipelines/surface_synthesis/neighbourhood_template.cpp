#include "pipelines/surface_synthesis/neighbourhood_template.hpp"

namespace texsim::pipelines::surface_synthesis {
namespace {

/// Offsets of a rows x cols block centred on 0, row by row.
std::vector<Eigen::Vector2d> block(int rows, int cols, bool skip_centre) {
  std::vector<Eigen::Vector2d> offsets;
  for (int r = 0; r < rows; ++r)
    for (int c = 0; c < cols; ++c) {
      const Eigen::Vector2d offset(c - 0.5 * (cols - 1), r - 0.5 * (rows - 1));
      if (!(skip_centre && offset.isZero()))
        offsets.push_back(offset);
    }
  return offsets;
}

std::vector<Eigen::Vector2d> flattened(const std::vector<Eigen::Vector2d>& offsets,
                                       double spacing) {
  std::vector<Eigen::Vector2d> positions;
  positions.reserve(offsets.size());
  for (const auto& o : offsets)
    positions.emplace_back(o.x() * spacing, -o.y() * spacing);
  return positions;
}

} // namespace

NeighbourhoodTemplate NeighbourhoodTemplate::from_shape(const NeighbourhoodShape& shape,
                                                        bool coarser_exists) {
  NeighbourhoodTemplate layout;
  layout.current = block(shape.rows, shape.cols, true);
  if (shape.levels == 2 && coarser_exists)
    layout.coarser = block((shape.rows + 1) / 2, (shape.cols + 1) / 2, false);
  return layout;
}

std::vector<Eigen::Vector2d> NeighbourhoodTemplate::current_positions(double d) const {
  return flattened(current, d);
}

std::vector<Eigen::Vector2d> NeighbourhoodTemplate::coarser_positions(double d) const {
  return flattened(coarser, 2 * d);
}

} // namespace texsim::pipelines::surface_synthesis
