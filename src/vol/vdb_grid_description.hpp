#pragma once
/// The name, transform and texsim metadata every dense grid texsim writes to a .vdb carries
/// (vol/vdb_io.hpp explains the metadata). Shared by the whole-tree writer in vdb_io.cpp and the
/// parallel layout in vdb_dense_layout.cpp so both describe a grid alike. Internal to vol.
#include "vol/dense_grid.hpp"

#include <array>
#include <string>

#include <openvdb/Grid.h>

namespace texsim::vol {

/// Names `grid`, gives it a scale-translate transform of spacing `spacing` and origin `origin`,
/// and stores its dense dims and exact spacing and origin as metadata.
void describe_dense_grid(openvdb::GridBase& grid, Dims dims, const std::array<double, 3>& spacing,
                         const std::array<double, 3>& origin, const std::string& grid_name);

/// Runs openvdb::initialize() once per process.
void initialize_openvdb();

} // namespace texsim::vol
