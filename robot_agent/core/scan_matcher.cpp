#include "robot_agent/core/scan_matcher.h"

namespace cairn::agent {

MatchingGrids build_matching_grids(const OccupancyGrid& grid, const ScanMatcherOptions& options) {
  MatchingGrids out;
  out.probability = ProbabilityGrid::from_occupancy(grid, options.unknown_probability);
  out.likelihood = out.probability.blurred(options.blur_sigma_cells);
  return out;
}

ScanMatcher::ScanMatcher(const ScanMatcherOptions& options)
    : options_(options), correlative_(options.correlative), ceres_(options.ceres) {}

ScanMatchResult ScanMatcher::match(const SE2& predicted, const std::vector<Eigen::Vector2f>& points,
                                   const MatchingGrids& grids) const {
  ScanMatchResult out;
  out.pose = predicted;
  if (points.empty()) {
    out.reason = "no points";
    return out;
  }
  if (grids.probability.width() == 0) {
    out.reason = "empty map";
    return out;
  }
  SE2 start = predicted;
  if (options_.use_correlative) {
    const CorrelativeMatch c = correlative_.match(predicted, points, grids.likelihood);
    start = c.pose;
    out.correlative_score = c.score;
  }
  const CeresMatch refined = ceres_.match(start, points, grids.probability);
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
