#pragma once
// Local 2D SLAM of one robot (Cartographer's LocalTrajectoryBuilder2D + PoseGraph2D, Hess et al.
// 2016): predict the pose from odometry (or constant velocity), skip near-duplicate scans with a
// motion filter, match the scan against the active submap (scan_matcher.h: real-time correlative
// search + Ceres), insert it into the submaps, and close loops against older submaps
// (submap_loop_closer.h, SubmapLoopCloser) so the robot's own map stays consistent over long runs.
#include <Eigen/Core>
#include <optional>
#include <vector>

#include "common/laser_scan.h"
#include "common/se2.h"
#include "common/time.h"
#include "common/trajectory.h"
#include "robot_agent/core/scan_matcher.h"
#include "robot_agent/core/submap.h"
#include "robot_agent/core/submap_loop_closer.h"

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
  SubmapLoopCloserOptions loop_closure;
  int min_valid_points = 20;  ///< fewer valid beams: the scan is skipped
  /// The correlative window grows with the predicted motion since the last matched scan (odometry
  /// error grows with distance): + this many metres per metre and radians per metre / per radian.
  double window_linear_per_m = 0.3;
  double window_angular_per_m_rad = 9.0 * M_PI / 180.0;
  double window_angular_per_rad = 0.1;
  double window_max_extra_linear_m = 0.5;
  double window_max_extra_angular_rad = 20.0 * M_PI / 180.0;
  double match_voxel_m = 0.08;  ///< points used for matching are thinned to one per cell (0 = all)
  /// Held odometry: a reading that repeats the previous one exactly while the scan's ranges moved
  /// away from those of the scan where that reading was new by more than this (median over the
  /// beams valid in both) is a dead or late odometry stream, not a standstill. The scan is skipped
  /// (kOdometryStalled) until a fresh reading arrives, whose step, from the pose before the stall,
  /// predicts the next match; without this the motion filter's max_time_s let a scan be matched
  /// from the held pose, metres off, and inserted. 0 disables.
  double held_odometry_scan_change_m = 0.03;
};

struct LocalSlamResult {
  enum class Status { kFirstScan, kMatched, kMotionFiltered, kTooFewPoints, kMatchFailed, kOdometryStalled };
  Status status = Status::kTooFewPoints;
  StampNs stamp_ns = 0;
  SE2 pose;        ///< T_local_base (matched, or predicted when not matched)
  SE2 T_map_base;  ///< the same pose after loop closure (optimised frame), at this time
  Covariance3 covariance = Covariance3::Identity();
  ScanMatchResult match;         ///< valid for kMatched / kMatchFailed
  bool inserted = false;         ///< went into the submaps
  ScanFilterStats filter_stats;  ///< this scan's beam filtering
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
  const SubmapLoopCloser& loop_closure() const { return loop_closure_; }
  /// End of input: final pose-graph optimisation.
  void finish() { loop_closure_.finish(); }
  /// Every processed scan's pose in the optimised frame (scans between nodes ride on the latest node
  /// before them), with the current optimisation state.
  Trajectory optimized_trajectory() const;

 private:
  SE2 predict(StampNs stamp_ns, const std::optional<SE2>& T_odom_base) const;
  bool motion_filtered(StampNs stamp_ns, const SE2& pose) const;
  void record_scan(StampNs stamp_ns, const SE2& T_local_base);
  void record_tracked(StampNs stamp_ns, const SE2& pose, const std::optional<SE2>& T_odom_base);
  void record_matched(StampNs stamp_ns, const SE2& pose);

  LocalSlamOptions options_;
  ScanMatcher matcher_;
  ActiveSubmaps submaps_;
  SubmapLoopCloser loop_closure_;
  struct ScanRecord {
    StampNs stamp_ns;
    int node;         ///< latest node at or before the scan (-1: before the first node)
    SE2 T_node_scan;  ///< or T_local_scan when node < 0
  };
  std::vector<ScanRecord> scan_records_;

  bool initialized_ = false;
  StampNs stamp_ns_ = 0;                      ///< of the latest tracked pose
  SE2 pose_;                                  ///< latest tracked pose
  std::optional<SE2> odom_;                   ///< odometry at the latest tracked pose
  std::vector<float> fresh_odometry_ranges_;  ///< ranges of the scan where odom_'s reading was new
  StampNs inserted_stamp_ns_ = 0;             ///< motion-filter reference
  SE2 inserted_pose_;
  bool has_inserted_ = false;
  /// Constant-velocity model: the last two matched poses.
  std::optional<std::pair<StampNs, SE2>> matched_prev_, matched_last_;
};

}  // namespace cairn::agent
