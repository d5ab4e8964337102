#pragma once
// Turk cells on a flat unit square (8000 by default), for tests of pattern measures whose
// expected values follow from plane geometry.
#include "geom/generators.hpp"
#include "geom/mesh_topology.hpp"
#include "geom/surface_cells.hpp"

#include <cstdint>
#include <functional>
#include <vector>

namespace texsim::pipelines::turk_rd::test {

struct SquareCells {
  par::Comm comm = par::world();
  geom::TriangleMesh mesh = geom::plane(geom::Vec3(1, 1, 0), 40);
  geom::SurfaceCells cells;

  explicit SquareCells(std::int64_t count = 8000)
      : cells(comm, geom::DistributedTriangles::from_replicated(comm, mesh), 4, settings(count)) {}

  /// `f` at every owned cell's position.
  template <class T> std::vector<T> at_cells(const std::function<T(const geom::Vec3&)>& f) const {
    std::vector<T> values;
    for (std::int32_t i = 0; i < cells.owned_count(); ++i)
      values.push_back(f(cells.points()[i].position));
    return values;
  }

private:
  static geom::SurfaceCellsSettings settings(std::int64_t count) {
    geom::SurfaceCellsSettings s;
    s.count = count;
    return s;
  }
};

} // namespace texsim::pipelines::turk_rd::test
