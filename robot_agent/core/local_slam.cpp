#include "robot_agent/core/local_slam.h"

#include <cmath>
#include <unordered_set>

namespace cairn::agent {

const char* to_string(LocalSlamResult::Status status) {
  switch (status) {
    case LocalSlamResult::Status::kFirstScan: return "first_scan";
    case LocalSlamResult::Status::kMatched: return "matched";
    case LocalSlamResult::Status::kMotionFiltered: return "motion_filtered";
    case LocalSlamResult::Status::kTooFewPoints: return "too_few_points";
    case LocalSlamResult::Status::kMatchFailed: return "match_failed";
  }
  return "unknown";
}

std::vector<Eigen::Vector2f> voxel_filter_2d(const std::vector<Eigen::Vector2f>& points, double voxel_m) {
  if (voxel_m <= 0.0) return points;
  std::unordered_set<int64_t> seen;
  std::vector<Eigen::Vector2f> out;
  out.reserve(points.size());
  for (const auto& p : points) {
    const int64_t cx = int64_t(std::floor(p.x() / voxel_m)), cy = int64_t(std::floor(p.y() / voxel_m));
    if (seen.insert((cx << 32) ^ (cy & 0xffffffff)).second) out.push_back(p);
  }
  return out;
}

LocalSlam::LocalSlam(const LocalSlamOptions& options)
    : options_(options), matcher_(options.matcher), submaps_(options.submaps) {}

SE2 LocalSlam::predict(StampNs stamp_ns, const std::optional<SE2>& T_odom_base) const {
  if (!initialized_) return SE2();
  if (T_odom_base && odom_) return pose_ * odom_->between(*T_odom_base);
  if (!matched_prev_ || !matched_last_) return pose_;
  // Constant velocity in the body frame, from the last two matched poses.
  const double dt_s = ns_to_sec(matched_last_->first - matched_prev_->first);
  if (dt_s <= 0.0) return pose_;
  const Eigen::Vector3d rate = matched_prev_->second.between(matched_last_->second).vector() / dt_s;
  const double elapsed_s = ns_to_sec(stamp_ns - stamp_ns_);
  return pose_ * SE2::from_vector(rate * elapsed_s);
}

bool LocalSlam::motion_filtered(StampNs stamp_ns, const SE2& pose) const {
  if (!has_inserted_) return false;
  const MotionFilterOptions& o = options_.motion_filter;
  if (ns_to_sec(stamp_ns - inserted_stamp_ns_) >= o.max_time_s) return false;
  const SE2 d = inserted_pose_.between(pose);
  return d.translation().norm() < o.max_distance_m && std::abs(d.yaw()) < o.max_angle_rad;
}

const MatchingGrids& LocalSlam::matching_grids() {
  if (grids_version_ != submaps_.matching_version()) {
    grids_ = build_matching_grids(submaps_.matching_submap().grid, options_.matcher);
    grids_version_ = submaps_.matching_version();
  }
  return grids_;
}

void LocalSlam::record_tracked(StampNs stamp_ns, const SE2& pose, const std::optional<SE2>& T_odom_base) {
  initialized_ = true;
  stamp_ns_ = stamp_ns;
  pose_ = pose;
  if (T_odom_base) odom_ = T_odom_base;
}

void LocalSlam::record_matched(StampNs stamp_ns, const SE2& pose) {
  matched_prev_ = matched_last_;
  matched_last_ = std::make_pair(stamp_ns, pose);
}

LocalSlamResult LocalSlam::add_scan(const LaserScan& scan, const std::optional<SE2>& T_odom_base) {
  LocalSlamResult out;
  out.stamp_ns = scan.stamp_ns;
  const std::vector<Eigen::Vector2f> points = scan_to_points(scan, &out.filter_stats);
  const SE2 predicted = predict(scan.stamp_ns, T_odom_base);
  out.pose = predicted;
  if (int(points.size()) < options_.min_valid_points) {
    out.status = LocalSlamResult::Status::kTooFewPoints;
    if (initialized_) record_tracked(scan.stamp_ns, predicted, T_odom_base);
    return out;
  }
  const bool has_odometry = T_odom_base && odom_;
  // With odometry the prediction is trusted enough to skip matching near-duplicate scans;
  // without it, every scan is matched (the filter then only gates insertion).
  if (has_odometry && motion_filtered(scan.stamp_ns, predicted)) {
    out.status = LocalSlamResult::Status::kMotionFiltered;
    record_tracked(scan.stamp_ns, predicted, T_odom_base);
    return out;
  }
  if (submaps_.empty()) {
    out.status = LocalSlamResult::Status::kFirstScan;
    out.covariance = Covariance3::Identity() * 1e-6;
  } else {
    out.match = matcher_.match(predicted, voxel_filter_2d(points, options_.match_voxel_m), matching_grids());
    if (!out.match.converged) {
      out.status = LocalSlamResult::Status::kMatchFailed;
      record_tracked(scan.stamp_ns, predicted, T_odom_base);
      return out;
    }
    out.status = LocalSlamResult::Status::kMatched;
    out.pose = out.match.pose;
    out.covariance = out.match.covariance;
  }
  record_tracked(scan.stamp_ns, out.pose, T_odom_base);
  record_matched(scan.stamp_ns, out.pose);
  if (has_odometry || !motion_filtered(scan.stamp_ns, out.pose)) {
    submaps_.insert(out.pose, points);
    out.inserted = true;
    has_inserted_ = true;
    inserted_stamp_ns_ = scan.stamp_ns;
    inserted_pose_ = out.pose;
  }
  return out;
}

}  // namespace cairn::agent
