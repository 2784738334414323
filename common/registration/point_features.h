#pragma once
// Per-point geometry for registration (Rusu et al. 2009): normals by PCA of the k nearest
// neighbours (oriented toward a viewpoint, as PCL does), FPFH descriptors (11 bins for each of the
// three Darboux-frame angles, SPFH of the point plus the 1/d^2-weighted SPFHs of its neighbours),
// and reciprocal nearest-neighbour matching in descriptor space filtered by colour. All queries
// go through KnnIndex in batches. Used by rgb_icp (Algorithm 3 step 1).
#include <Eigen/Core>
#include <array>
#include <utility>
#include <vector>

#include "common/point_cloud.h"
#include "common/registration/knn_index.h"

namespace cairn::registration {

using Fpfh = std::array<float, 33>;

/// xyz rows of a cloud, for KnnIndex.
std::vector<float> xyz_rows(const ColoredCloud& cloud);

/// Unit normals (NaN where fewer than 3 neighbours), flipped toward `viewpoint`.
std::vector<Eigen::Vector3f> estimate_normals(const ColoredCloud& cloud, const KnnIndex& xyz_index, int k,
                                              const Eigen::Vector3f& viewpoint = Eigen::Vector3f::Zero());

/// FPFH over neighbours within radius_m; all-zero for points without a usable neighbourhood.
std::vector<Fpfh> compute_fpfh(const ColoredCloud& cloud, const std::vector<Eigen::Vector3f>& normals,
                               const KnnIndex& xyz_index, double radius_m);

/// Reciprocal nearest neighbours in FPFH space whose RGB distance is at most max_colour_diff.
std::vector<std::pair<int, int>> match_features(const ColoredCloud& source, const std::vector<Fpfh>& fs,
                                                const ColoredCloud& target, const std::vector<Fpfh>& ft,
                                                double max_colour_diff);

}  // namespace cairn::registration
