#pragma once
/// Turk's initiator cells: cells frozen at chosen values so that a pattern radiates from them (the
/// pseudo-zebra's stripes start at a few cells on the head and the hooves).
#include "geom/surface_cells.hpp"
#include "par/comm.hpp"
#include "pipelines/turk_rd/turk_rd_settings.hpp"

#include <span>
#include <string>
#include <vector>

namespace texsim::pipelines::turk_rd {

/// 1 for every owned cell the initiator selects: the cell nearest to `at` (ties to the lower id)
/// and every cell within `radius` of it, or every cell where `region` is nonzero (`region` may use
/// the per-cell arrays `names`, given in `columns`). Throws InputError naming the initiator when
/// it selects no cell at all. Collective.
std::vector<char> select_initiator_cells(const par::Comm& comm, const geom::SurfaceCells& cells,
                                         const InitiatorSettings& initiator,
                                         const std::vector<std::string>& names = {},
                                         const std::vector<std::span<const double>>& columns = {});

} // namespace texsim::pipelines::turk_rd
