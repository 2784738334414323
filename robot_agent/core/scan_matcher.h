#pragma once
// Scan-to-submap matching as Cartographer's local SLAM does it: a real-time correlative search
// (Olson 2009) around the predicted pose on the probability grid (optionally a Gaussian-smoothed
// copy), then a Ceres refinement on the bicubic-interpolated probability grid (ceres_scan_matcher.h).
#include <Eigen/Core>
#include <string>
#include <vector>

#include "common/occupancy_grid.h"
#include "common/se2.h"
#include "robot_agent/core/ceres_scan_matcher.h"
#include "robot_agent/core/correlative_scan_matcher.h"
#include "robot_agent/core/probability_grid.h"

namespace cairn::agent {

struct ScanMatcherOptions {
  CorrelativeScanMatcherOptions correlative;
  CeresScanMatcherOptions ceres;
  bool use_correlative = true;       ///< false: Ceres only, starting at the prediction
  float unknown_probability = 0.1f;  ///< probability given to unexplored cells
  /// Smoothing of the correlative likelihood grid in build_matching_grids (0: search the probability
  /// grid itself; the local SLAM never blurs, so no grid is rebuilt per scan).
  double blur_sigma_cells = 0.0;
  /// A match whose final interpolated score is below this is reported as not converged.
  double min_score = 0.12;
};

/// The two grids the matcher needs, built once per submap change.
struct MatchingGrids {
  ProbabilityGrid probability;  ///< for the Ceres refinement
  ProbabilityGrid likelihood;   ///< smoothed, for the correlative search (empty: use probability)
};
MatchingGrids build_matching_grids(const OccupancyGrid& grid, const ScanMatcherOptions& options);

struct ScanMatchResult {
  SE2 pose;            ///< T_map_base
  double score = 0.0;  ///< mean interpolated probability at the points, 0..1
  double correlative_score = 0.0;
  int correlative_candidates = 0;
  bool converged = false;
  Covariance3 covariance = Covariance3::Identity();
  std::string reason;  ///< why not converged; empty otherwise
};

class ScanMatcher {
 public:
  explicit ScanMatcher(const ScanMatcherOptions& options = {});

  ScanMatchResult match(const SE2& predicted_T_map_base, const std::vector<Eigen::Vector2f>& points_base,
                        const MatchingGrids& grids) const;
  /// Searches and refines on one grid (the live submap grid, no copies).
  /// `extra_*` widen the correlative window beyond the options' (uncertain predictions).
  ScanMatchResult match(const SE2& predicted_T_map_base, const std::vector<Eigen::Vector2f>& points_base,
                        const ProbabilityGrid& grid, double extra_linear_m = 0.0, double extra_angular_rad = 0.0) const;
  const ScanMatcherOptions& options() const { return options_; }

 private:
  ScanMatcherOptions options_;
  CorrelativeScanMatcher correlative_;
  CeresScanMatcher ceres_;
};

}  // namespace cairn::agent
