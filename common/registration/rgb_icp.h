#pragma once
// RGB-ICP, the seed paper's Algorithm 3 ("improved ICP"): (1) RGB point features on both clouds
// (FPFH geometry descriptors, matched reciprocally in descriptor space and filtered by colour),
// (2) RANSAC alignment of the matches (3-point samples, Umeyama, edge-length pre-check, adaptive
// stop at ransac_confidence); when fewer than `min_inliers` (the paper's r) survive, the prior pose
// T_p is kept; the better of RANSAC and prior (by overlap) seeds (3) ICP: closest points in a joint
// xyz + colour space (Johnson & Kang), point-to-plane Gauss-Newton steps with target normals
// computed once, until the pose change is below delta or the iterations run out.
// Residual: sum_i w_i (n_i . (T s_i - t_i))^2, w_i down-weights colour disagreement.
// Neutral library `cairn_registration` (agent view fusion and base duplicate merging both use it);
// no PCL or FLANN in this header.
#include <Eigen/Geometry>
#include <string>

#include "common/point_cloud.h"

namespace cairn::registration {

struct RgbIcpOptions {
  double voxel_m = 0.01;     ///< both clouds are voxel-filtered first (<= 0: not)
  bool use_features = true;  ///< false: ICP from the prior only
  /// Features + RANSAC run on clouds voxel-filtered to this (<= voxel_m: the ICP clouds).
  double feature_voxel_m = 0.0;
  int normal_neighbours = 15;
  double feature_radius_m = 0.05;         ///< FPFH support
  double max_feature_colour_diff = 80.0;  ///< RGB distance for a feature match (coloured clouds)
  int ransac_iterations = 4000;           ///< upper bound; the adaptive stop usually ends far sooner
  double ransac_confidence = 0.999;       ///< stop once a better sample is this unlikely to be missed
  double ransac_edge_similarity = 0.9;    ///< sampled triangles' edge ratios must exceed this
  double ransac_inlier_m = 0.02;
  int min_inliers = 12;                ///< r of Algorithm 3
  double max_correspondence_m = 0.05;  ///< ICP closest-point gate
  double colour_scale_m = 0.0004;      ///< metres per RGB unit in the joint search (0: geometry only)
  int max_iterations = 50;
  /// Directions of the point-to-plane normal matrix whose eigenvalue is below this fraction of the
  /// largest are unobservable: no step along them, result flagged degenerate.
  double min_eigen_ratio = 1e-6;
  double delta_translation_m = 1e-5;  ///< delta of Algorithm 3
  double delta_rotation_rad = 1e-5;
  int min_points = 10;
  unsigned seed = 1;
};

struct RgbIcpResult {
  Eigen::Isometry3d T_target_source = Eigen::Isometry3d::Identity();
  bool converged = false;   ///< ICP stopped on delta with enough overlap
  bool degenerate = false;  ///< some of the 6 DoF unobservable (plane, line, sphere-like)
  double score = 0.0;       ///< fitness: fraction of source points within max_correspondence_m
  double rmse_m = 0.0;      ///< of those correspondences
  int feature_matches = 0;
  int feature_inliers = 0;    ///< RANSAC inliers (|A_f|)
  int ransac_iterations = 0;  ///< samples drawn before the adaptive stop
  bool used_prior = true;     ///< the prior, not RANSAC, seeded ICP
  int iterations = 0;
  std::string reason;  ///< why not converged (empty when converged)
};

/// Aligns `source` onto `target`; T_prior maps source into target coordinates (T_p).
RgbIcpResult rgb_icp(const ColoredCloud& source, const ColoredCloud& target,
                     const Eigen::Isometry3d& T_prior = Eigen::Isometry3d::Identity(),
                     const RgbIcpOptions& options = {});

/// Averages points (position and colour) per cubic voxel of voxel_m; drops non-finite points;
/// deterministic output order (voxel key order). voxel_m <= 0 only drops non-finite points.
ColoredCloud voxel_grid(const ColoredCloud& cloud, double voxel_m);

}  // namespace cairn::registration
