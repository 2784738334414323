#pragma once
// Loop-closure verification by scan matching, without an initial guess beyond a search window:
// the query scan is matched against a local map of the candidate's neighbouring keyframes with a
// branch-and-bound correlative search (Hess et al., "Real-Time Loop Closure in 2D LIDAR SLAM",
// ICRA 2016; Cartographer's FastCorrelativeScanMatcher2D: max-pooled precomputation grids, depth-
// first search with pruning by an upper bound), then refined by point-to-point ICP (Gauss-Newton)
// whose Hessian gives the covariance. A match counts only above a score and an inlier fraction.
#include <Eigen/Core>
#include <optional>
#include <string>
#include <vector>

#include "common/se2.h"

namespace cairn::base {

struct LoopVerifierOptions {
  double resolution_m = 0.05;          ///< finest grid of the correlative search
  double blur_sigma_m = 0.08;          ///< smoothing of the likelihood grid
  int branch_and_bound_depth = 6;      ///< precomputation grids 1, 2, 4, ... 2^(depth-1) cells
  double linear_window_m = 4.0;        ///< search +- this around the initial translation
  double angular_window_rad = M_PI;    ///< search +- this around the initial yaw (pi: full circle)
  double max_range_for_step_m = 12.0;  ///< sets the angular step (one cell at this range)
  double min_score = 0.55;             ///< mean likelihood at the query points, 0..1
  double icp_inlier_distance_m = 0.15;
  double min_inlier_fraction = 0.6;  ///< of query points within icp_inlier_distance_m after ICP
  int icp_iterations = 15;
  double min_covariance_sigma_m = 0.02;  ///< floors of the estimated covariance
  double min_covariance_sigma_rad = 0.005;
  int min_points = 40;
};

struct LoopVerification {
  bool accepted = false;
  SE2 T_map_query;     ///< pose of the query sensor frame in the local-map frame
  double score = 0.0;  ///< correlative score of the best candidate
  double inlier_fraction = 0.0;
  Covariance3 covariance = Covariance3::Identity();
  int candidates_scored = 0;
  std::string reason;  ///< why rejected
};

/// Matches `query_points` (query sensor frame) into `map_points` (local-map frame) searching the
/// window around `initial_T_map_query`.
LoopVerification verify_loop(const std::vector<Eigen::Vector2f>& map_points,
                             const std::vector<Eigen::Vector2f>& query_points, const SE2& initial_T_map_query,
                             const LoopVerifierOptions& options = {});

}  // namespace cairn::base
