#pragma once
/// Quality measures of a synthesized solid texture against its exemplar, for run reports and
/// tests: how well its neighbourhoods match the exemplar's (the quantity the synthesis
/// minimises), how close its colour distribution is, and which way its stripes run.
#include "pipelines/solid_synthesis/feature_kd_tree.hpp"
#include "vol/channel_grid.hpp"

#include <functional>
#include <span>
#include <vector>

namespace texsim::pipelines::solid_synthesis {

/// Writes the appearance vector of the 5^3 neighbourhood centred on voxel (i, j, k) of a colour
/// grid into `out` (periodic lookups in the grid). Called concurrently from OpenMP threads.
using NeighbourhoodProjection =
    std::function<void(const vol::ChannelGrid&, int, int, int, std::span<float>)>;

/// Mean Euclidean distance, over the result voxels whose coordinates are all multiples of
/// `stride`, from the appearance vector `project` gives for the result's neighbourhood to the
/// nearest exemplar appearance vector (a voxel of `exemplar_features`, whose channel count is
/// the appearance dimension; exact search), divided by the mean distance of the exemplar's
/// appearance vectors to their mean, so the value does not depend on the feature scale: 0 when
/// every sampled neighbourhood occurs in the exemplar. Deterministic; not collective.
double neighbourhood_error(const vol::ChannelGrid& result_colours,
                           const vol::ChannelGrid& exemplar_features,
                           const NeighbourhoodProjection& project, int stride);

/// The scale of neighbourhood_error: the mean Euclidean distance of the exemplar's appearance
/// vectors (the voxels of `exemplar_features`) to their mean. Throws Error if it is 0.
double appearance_spread(const vol::ChannelGrid& exemplar_features);

/// For each query (rows of `queries`, the features' channel count each), the Euclidean distance
/// to the nearest exemplar appearance vector: the square root of the least exact_feature_distance
/// over all exemplar voxels (found through a kd-tree over the distinct vectors,
/// distinct_feature_rows: the same bits as a full scan), whichever other queries it is asked with
/// and however many threads share them.
std::vector<double> nearest_appearance_distances(std::span<const float> queries,
                                                 const vol::ChannelGrid& exemplar_features);
/// The same distances through `tree`, built over `exemplar_features` (one held per node, say;
/// pass distinct rows, or exact ties in flat regions are all visited).
std::vector<double> nearest_appearance_distances(std::span<const float> queries,
                                                 const vol::ChannelGrid& exemplar_features,
                                                 const FeatureKdTree& tree);

/// Total variation distance (0..1) between the joint colour histograms (8 bins per channel,
/// values clamped to [0, 1]) of two grids with the same channel count (1 to 4); the grids may have
/// different sizes.
double histogram_distance(const vol::ChannelGrid& a, const vol::ChannelGrid& b);

/// Dominant stripe orientation in XY planes: the angle in degrees, in (-90, 90], from the x axis
/// towards y, of the direction ALONG which the pattern is constant, from the gradient structure
/// tensor of the luminance (1 channel: the value; 3: Rec. 709 weights) summed over all XY planes
/// (central differences, periodic). Stripes varying along y only give 0.
double xy_stripe_orientation_degrees(const vol::ChannelGrid& colours);

} // namespace texsim::pipelines::solid_synthesis
