#pragma once
// Real-time correlative scan matching (Olson, "Real-Time Correlative Scan Matching", ICRA 2009;
// Cartographer's RealTimeCorrelativeScanMatcher2D): an exhaustive search over a window of
// translations and rotations around a predicted pose, scoring each candidate by the mean of the
// grid's likelihood field (probability_grid.h) at the transformed scan points. The scan is rotated and discretised once
// per angle (precomputed rotated scans); each point then adds its row of grid values to a score array over the whole
// translation window, reading only the cropped part of the grid. Its result seeds the Ceres refinement.
#include <Eigen/Core>
#include <vector>

#include "common/se2.h"
#include "robot_agent/core/probability_grid.h"

namespace cairn::agent {

struct CorrelativeScanMatcherOptions {
  double linear_window_m = 0.1;                    ///< search +- this in x and y
  double angular_window_rad = 5.0 * M_PI / 180.0;  ///< search +- this in yaw
  /// The angular step keeps the farthest point (capped at this range) within one cell per step.
  double max_range_for_step_m = 8.0;
  /// Candidate score is multiplied by exp(-(w_t*|dt|)^2 - (w_r*|dyaw|)^2) (Cartographer's
  /// translation/rotation_delta_cost_weight), preferring the prediction among equal scores.
  double translation_delta_cost_weight = 0.1;
  double rotation_delta_cost_weight = 0.1;
};

struct CorrelativeMatch {
  SE2 pose;
  double score = 0.0;  ///< mean likelihood field at the points of the best candidate, 0..1
  int candidates = 0;  ///< candidates evaluated
};

class CorrelativeScanMatcher {
 public:
  explicit CorrelativeScanMatcher(const CorrelativeScanMatcherOptions& options = {});

  /// `points_base` are scan points in the robot base frame; `likelihood` is the probability grid (or
  /// a smoothed copy) in the map frame. Returns the best candidate (score 0 when there are no points).
  CorrelativeMatch match(const SE2& initial_T_map_base, const std::vector<Eigen::Vector2f>& points_base,
                         const ProbabilityGrid& likelihood) const {
    return match(initial_T_map_base, points_base, likelihood, options_.linear_window_m, options_.angular_window_rad);
  }
  /// The same with an explicit search window (e.g. grown with the odometry's uncertainty).
  CorrelativeMatch match(const SE2& initial_T_map_base, const std::vector<Eigen::Vector2f>& points_base,
                         const ProbabilityGrid& likelihood, double linear_window_m, double angular_window_rad) const;

  /// Angular step (rad) so that a point at `range_m` moves by about one cell of `resolution_m`.
  static double angular_step_rad(double range_m, double resolution_m);

 private:
  CorrelativeScanMatcherOptions options_;
};

/// Translation covariance of a match from its score surface (Olson 2009, Sec. IV): the mean
/// likelihood field s(d) of the scan shifted by d over a (2k+1)^2 lattice around the match, turned
/// into weights p(d) = exp((s(d) - max s) / temperature), gives Sigma = sum p d d^T / sum p -
/// mu mu^T. Along a featureless corridor s stays flat, so the variance there is that of the window
/// (its shape, not its absolute value, is what covariance weighting uses).
struct ScoreSurfaceOptions {
  /// Shifts up to +- this in x and y: bounds the variance a flat direction can get (ACES seeds 1-3,
  /// window 0.3 / 0.5 / 0.8 m: ATE 0.144 / 0.128 / 0.129, 0.307 / 0.229 / 0.187, 0.208 / 0.196 / 0.192 m).
  double window_m = 0.8;
  /// Lattice step, rounded to whole cells; more than the field's width (~1 cell) would miss a
  /// corridor at an angle to the grid (its along-axis shifts fall between lattice points).
  double step_m = 0.05;
  double temperature = 0.05;  ///< score drop (0..1 scale) that lowers the weight by e
  int max_points = 30;        ///< every k-th point so that at most this many are scored (cost)
};
Eigen::Matrix2d score_surface_covariance(const ProbabilityGrid& grid, const SE2& T_grid_base,
                                         const std::vector<Eigen::Vector2f>& points_base,
                                         const ScoreSurfaceOptions& options = {});
/// The covariance of a (2k+1)^2 lattice of scores (row-major, y rows; spacing lattice_step_m):
/// weights exp((score - max) / temperature), plus the variance of a uniform step-wide cell.
Eigen::Matrix2d covariance_of_score_lattice(const std::vector<double>& score, int k, double lattice_step_m,
                                            double temperature);

}  // namespace cairn::agent
