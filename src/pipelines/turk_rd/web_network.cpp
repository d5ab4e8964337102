#include "pipelines/turk_rd/web_network.hpp"

#include "pipelines/turk_rd/region_moments.hpp"

#include <mpi.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <vector>

namespace texsim::pipelines::turk_rd {

WebNetwork measure_web(const par::Comm& comm, const geom::SurfaceCells& cells,
                       std::span<const char> web) {
  std::vector<char> patch(web.size());
  std::transform(web.begin(), web.end(), patch.begin(), [](char w) { return char(!w); });
  const auto webs = region_moments_on_root(comm, cells, label_cell_regions(comm, cells, web));
  const auto patches = region_moments_on_root(comm, cells, label_cell_regions(comm, cells, patch));
  double result[6] = {0, 0, 0, 0, 0, 0};
  if (comm.is_root()) {
    double web_area = 0, largest = 0, border = 0, patch_area = 0;
    for (const RegionMoments& region : webs) {
      web_area += region.area;
      largest = std::max(largest, region.area);
      border += region.perimeter;
    }
    std::vector<double> areas;
    for (const RegionMoments& region : patches) {
      patch_area += region.area;
      areas.push_back(region.area);
    }
    std::sort(areas.begin(), areas.end());
    const double total = web_area + patch_area;
    result[0] = total > 0 ? web_area / total : 0.0;
    result[1] = double(webs.size());
    result[2] = web_area > 0 ? largest / web_area : 0.0;
    result[3] = double(patches.size());
    result[4] = border > 0 ? 2 * web_area / border : 0.0;
    result[5] = areas.empty() ? 0.0 : 2 * std::sqrt(areas[areas.size() / 2] / std::numbers::pi);
  }
  MPI_Bcast(result, 6, MPI_DOUBLE, 0, comm.raw);
  return {result[0], int(result[1]), result[2], int(result[3]), result[4], result[5]};
}

} // namespace texsim::pipelines::turk_rd
