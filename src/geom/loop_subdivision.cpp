#include "geom/loop_subdivision.hpp"

#include "core/error.hpp"
#include "geom/patch_refinement.hpp"

#include <vector>

namespace texsim::geom {

TriangleMesh loop_subdivide(const TriangleMesh& mesh, int levels) {
  TEXSIM_VERIFY(levels >= 0, "loop_subdivide: levels " << levels << " must be >= 0");
  const std::vector<RefinementStep> steps(std::size_t(levels), RefinementStep{});
  return refine(mesh, steps);
}

} // namespace texsim::geom
