#pragma once
// Local 2D SLAM of one robot (Cartographer's LocalTrajectoryBuilder2D, Hess et al. 2016): predict
// the pose from odometry (or constant velocity), skip near-duplicate scans with a motion filter,
// match the scan against the active submap (scan_matcher.h), insert it into the submaps.
#include <Eigen/Core>
#include <optional>
#include <vector>

#include "common/laser_scan.h"
#include "common/se2.h"
#include "common/time.h"
#include "robot_agent/core/scan_matcher.h"
#include "robot_agent/core/submap.h"

namespace cairn::agent {

/// A scan is "not new" when it moved less than both distances within max_time_s.
struct MotionFilterOptions {
  double max_time_s = 5.0;
  double max_distance_m = 0.05;
  double max_angle_rad = 1.0 * M_PI / 180.0;
};

struct LocalSlamOptions {
  SubmapOptions submaps;
  ScanMatcherOptions matcher;
  MotionFilterOptions motion_filter;
  int min_valid_points = 20;     ///< fewer valid beams: the scan is skipped
  double match_voxel_m = 0.05;   ///< points used for matching are thinned to one per cell (0 = all)
};

struct LocalSlamResult {
  enum class Status { kFirstScan, kMatched, kMotionFiltered, kTooFewPoints, kMatchFailed };
  Status status = Status::kTooFewPoints;
  StampNs stamp_ns = 0;
  SE2 pose;                       ///< T_local_base (matched, or predicted when not matched)
  Covariance3 covariance = Covariance3::Identity();
  ScanMatchResult match;          ///< valid for kMatched / kMatchFailed
  bool inserted = false;          ///< went into the submaps
  ScanFilterStats filter_stats;   ///< this scan's beam filtering
  bool matched() const { return status == Status::kMatched || status == Status::kFirstScan; }
};
const char* to_string(LocalSlamResult::Status status);

class LocalSlam {
 public:
  explicit LocalSlam(const LocalSlamOptions& options = {});

  /// Processes one scan. `T_odom_base` is the odometry pose at the scan's stamp, when available.
  LocalSlamResult add_scan(const LaserScan& scan, const std::optional<SE2>& T_odom_base);

  /// Latest tracked pose (matched or predicted).
  const SE2& pose() const { return pose_; }
  const ActiveSubmaps& submaps() const { return submaps_; }

 private:
  SE2 predict(StampNs stamp_ns, const std::optional<SE2>& T_odom_base) const;
  bool motion_filtered(StampNs stamp_ns, const SE2& pose) const;
  const MatchingGrids& matching_grids();
  void record_tracked(StampNs stamp_ns, const SE2& pose, const std::optional<SE2>& T_odom_base);
  void record_matched(StampNs stamp_ns, const SE2& pose);

  LocalSlamOptions options_;
  ScanMatcher matcher_;
  ActiveSubmaps submaps_;
  MatchingGrids grids_;
  int64_t grids_version_ = -1;

  bool initialized_ = false;
  StampNs stamp_ns_ = 0;               ///< of the latest tracked pose
  SE2 pose_;                           ///< latest tracked pose
  std::optional<SE2> odom_;            ///< odometry at the latest tracked pose
  StampNs inserted_stamp_ns_ = 0;      ///< motion-filter reference
  SE2 inserted_pose_;
  bool has_inserted_ = false;
  /// Constant-velocity model: the last two matched poses.
  std::optional<std::pair<StampNs, SE2>> matched_prev_, matched_last_;
};

/// Keeps the first point per cell of `voxel_m` (scan order), so dense scans cost less to match.
std::vector<Eigen::Vector2f> voxel_filter_2d(const std::vector<Eigen::Vector2f>& points, double voxel_m);

}  // namespace cairn::agent
