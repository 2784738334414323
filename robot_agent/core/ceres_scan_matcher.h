#pragma once
// Scan-to-grid refinement by non-linear least squares (Cartographer's CeresScanMatcher2D, after
// Kohlbrecher et al., "Hector SLAM", 2011): minimises over the pose (x, y, yaw)
//   sum_i (w_occ / sqrt(N) * (1 - P(T * p_i)))^2 + (w_t * (t - t0))^2 + (w_r * (yaw - yaw0))^2
// where P is the bicubic interpolation of the probability grid (or of its likelihood field) and
// (t0, yaw0) the initial guess.
#include <Eigen/Core>
#include <string>
#include <vector>

#include "common/se2.h"
#include "robot_agent/core/probability_grid.h"

namespace cairn::agent {

struct CeresScanMatcherOptions {
  double occupied_space_weight = 1.0;
  double translation_weight = 1.0;  ///< regulariser toward the initial translation
  double rotation_weight = 1.0;     ///< regulariser toward the initial yaw
  int max_num_iterations = 10;
  /// Match against the grid's likelihood field (symmetric Gaussian around hits) instead of the
  /// probabilities (whose unknown cells behind walls read 0.1 and free cells ~0.4, an asymmetry that
  /// pulls sparse scans toward free space).
  bool use_likelihood_field = true;
  /// Floor added to the Hessian-derived covariance (the Gauss-Newton estimate is optimistic).
  double min_translation_variance_m2 = 1e-4;
  double min_rotation_variance_rad2 = 1e-4;
  /// Compute CeresMatch::covariance (one more pass over the points); off where it is not read (the
  /// loop-closure refinement weights its constraints by the score surface instead).
  bool compute_covariance = true;
};

struct CeresMatch {
  SE2 pose;
  double score = 0.0;  ///< mean interpolated probability at the points, 0..1
  bool converged = false;
  Covariance3 covariance = Covariance3::Identity();
  std::string reason;  ///< empty when converged
};

class CeresScanMatcher {
 public:
  explicit CeresScanMatcher(const CeresScanMatcherOptions& options = {});

  /// `grid` holds probabilities (not smoothed); `points_base` in the base frame.
  CeresMatch match(const SE2& initial_T_map_base, const std::vector<Eigen::Vector2f>& points_base,
                   const ProbabilityGrid& grid) const;

 private:
  CeresScanMatcherOptions options_;
};

/// Mean bicubic-interpolated probability of `grid` at `points_base` placed by `T_map_base`.
double interpolated_score(const SE2& T_map_base, const std::vector<Eigen::Vector2f>& points_base,
                          const ProbabilityGrid& grid);

}  // namespace cairn::agent
