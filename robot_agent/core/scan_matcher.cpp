#include "robot_agent/core/scan_matcher.h"

namespace cairn::agent {

MatchingGrids build_matching_grids(const OccupancyGrid& grid, const ScanMatcherOptions& options) {
  MatchingGrids out;
  out.probability = ProbabilityGrid::from_occupancy(grid, options.unknown_probability);
  if (options.blur_sigma_cells > 0.0) out.likelihood = out.probability.blurred(options.blur_sigma_cells);
  return out;
}

ScanMatcher::ScanMatcher(const ScanMatcherOptions& options)
    : options_(options), correlative_(options.correlative), ceres_(options.ceres) {}

ScanMatchResult ScanMatcher::match(const SE2& predicted, const std::vector<Eigen::Vector2f>& points,
                                   const MatchingGrids& grids) const {
  if (grids.likelihood.width() == 0 || !options_.use_correlative) return match(predicted, points, grids.probability);
  ScanMatchResult out;
  out.pose = predicted;
  if (points.empty() || grids.probability.width() == 0) {
    out.reason = points.empty() ? "no points" : "empty map";
    return out;
  }
  const CorrelativeMatch c = correlative_.match(predicted, points, grids.likelihood);
  ScanMatcherOptions ceres_only = options_;
  ceres_only.use_correlative = false;
  out = ScanMatcher(ceres_only).match(c.pose, points, grids.probability);
  out.correlative_score = c.score;
  return out;
}

ScanMatchResult ScanMatcher::match(const SE2& predicted, const std::vector<Eigen::Vector2f>& points,
                                   const ProbabilityGrid& grid, double extra_linear_m, double extra_angular_rad) const {
  ScanMatchResult out;
  out.pose = predicted;
  if (points.empty()) {
    out.reason = "no points";
    return out;
  }
  if (grid.width() == 0) {
    out.reason = "empty map";
    return out;
  }
  SE2 start = predicted;
  if (options_.use_correlative) {
    const CorrelativeMatch c =
        correlative_.match(predicted, points, grid, options_.correlative.linear_window_m + extra_linear_m,
                           options_.correlative.angular_window_rad + extra_angular_rad);
    start = c.pose;
    out.correlative_score = c.score;
    out.correlative_candidates = c.candidates;
  }
  const CeresMatch refined = ceres_.match(start, points, grid);
  out.pose = refined.pose;
  out.score = refined.score;
  out.covariance = refined.covariance;
  out.converged = refined.converged;
  out.reason = refined.reason;
  if (out.converged && out.score < options_.min_score) {
    out.converged = false;
    out.reason = "score " + std::to_string(out.score) + " below min_score";
  }
  return out;
}

}  // namespace cairn::agent
