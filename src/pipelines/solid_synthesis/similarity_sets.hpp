#pragma once
/// Exact k-coherence similarity sets with exclusion windows (Su 2008, section 3.2, after Tong et
/// al.'s k-coherence search): for every exemplar voxel p, C_1(p) = p and C_{i+1}(p) is the voxel
/// whose features are nearest to p's among the voxels outside the n x n x n windows centred on
/// C_1(p) ... C_i(p). The synthesis' correction step draws its candidates from these sets.
#include "par/comm.hpp"
#include "par/node_shared_array.hpp"
#include "pipelines/solid_synthesis/nearest_outside_windows.hpp"
#include "vol/channel_grid.hpp"

#include <cstdint>
#include <vector>

namespace texsim::pipelines::solid_synthesis {

/// How similarity sets are built.
struct SimilarityOptions {
  /// Candidates per voxel, p itself included.
  int k = 3;
  /// Exclusion window edge n in voxels: a window holds the voxels with |dx|, |dy|, |dz| <= n / 2.
  int window = 7;
  /// Toroidal differences for the windows (a tileable exemplar); plain ones otherwise.
  bool periodic = true;
  /// kd-tree, brute-force scan, or whichever suits the features: the same sets, at different cost.
  ShortlistSearch search = ShortlistSearch::automatic;
};

/// candidates[v * k + i] = C_{i+1}(v) as a voxel storage index (x fastest); C_1(v) = v. Held
/// once per node: every rank reads them, none changes them.
struct SimilaritySets {
  vol::Dims dims;
  int k = 0;
  par::NodeSharedArray<std::int32_t> candidates;
};

/// The similarity sets of `features` (any number of float channels per voxel). Distances are
/// squared Euclidean, evaluated as the sum of (double(f_q) - double(f_p))^2 in channel order; ties
/// go to the smaller voxel index; when no voxel is left outside the windows (tiny exemplars) the
/// last candidate repeats. Exact: the same sets as a brute-force search, for any rank and thread
/// count. Collective over `comm`: ranks split the voxels into contiguous ranges (OpenMP threads
/// share a rank's range) and every rank returns the full sets (node-shared). A query with k - 1
/// identical-feature twins outside the windows (feature_twins; rank 0 sorts all voxels once,
/// O(N log N), and the groups are held once per node, like the kd-tree) takes them without a
/// search. The scan costs about 2 d N^2 flops; the tree visits
/// only the voxels within each query's witness distance.
SimilaritySets build_similarity_sets(const par::Comm& comm, const vol::ChannelGrid& features,
                                     const SimilarityOptions& options);

} // namespace texsim::pipelines::solid_synthesis
