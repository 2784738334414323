#include "robot_agent/core/local_slam.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace cairn::agent {

namespace {

// Median |a_i - b_i| over the beams with a valid range in both (same beam count); +inf when none or
// the counts differ.
double median_range_change_m(const LaserScan& a, const std::vector<float>& b) {
  if (a.ranges_m.size() != b.size()) return std::numeric_limits<double>::infinity();
  const auto valid = [&](float r) { return std::isfinite(r) && r > a.range_min_m && r < a.range_max_m; };
  std::vector<float> d;
  d.reserve(b.size());
  for (size_t i = 0; i < b.size(); ++i) {
    if (valid(a.ranges_m[i]) && valid(b[i])) d.push_back(std::abs(a.ranges_m[i] - b[i]));
  }
  if (d.empty()) return std::numeric_limits<double>::infinity();
  std::nth_element(d.begin(), d.begin() + long(d.size() / 2), d.end());
  return d[d.size() / 2];
}

}  // namespace

const char* to_string(LocalSlamResult::Status status) {
  switch (status) {
    case LocalSlamResult::Status::kFirstScan:
      return "first_scan";
    case LocalSlamResult::Status::kMatched:
      return "matched";
    case LocalSlamResult::Status::kMotionFiltered:
      return "motion_filtered";
    case LocalSlamResult::Status::kTooFewPoints:
      return "too_few_points";
    case LocalSlamResult::Status::kMatchFailed:
      return "match_failed";
    case LocalSlamResult::Status::kOdometryStalled:
      return "odometry_stalled";
  }
  return "unknown";
}

LocalSlam::LocalSlam(const LocalSlamOptions& options)
    : options_(options), matcher_(options.matcher), submaps_(options.submaps), loop_closure_(options.loop_closure) {}

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

void LocalSlam::record_scan(StampNs stamp_ns, const SE2& T_local_base) {
  const int node = loop_closure_.num_nodes() - 1;
  const SE2 rel = node < 0 ? T_local_base : loop_closure_.local_node_pose(node).between(T_local_base);
  scan_records_.push_back({stamp_ns, node, rel});
}

Trajectory LocalSlam::optimized_trajectory() const {
  Trajectory out;
  out.reserve(scan_records_.size());
  for (const ScanRecord& r : scan_records_) {
    out.push_back({r.stamp_ns, r.node < 0 ? r.T_node_scan : loop_closure_.node_pose(r.node) * r.T_node_scan});
  }
  return out;
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
  out.T_map_base = loop_closure_.T_global_local() * predicted;
  if (int(points.size()) < options_.min_valid_points) {
    out.status = LocalSlamResult::Status::kTooFewPoints;
    if (initialized_) {
      record_tracked(scan.stamp_ns, predicted, T_odom_base);
      record_scan(scan.stamp_ns, predicted);
    }
    return out;
  }
  const bool has_odometry = T_odom_base && odom_;
  const bool held = has_odometry && T_odom_base->x() == odom_->x() && T_odom_base->y() == odom_->y() &&
                    T_odom_base->yaw() == odom_->yaw();
  if (!held) fresh_odometry_ranges_ = scan.ranges_m;
  if (held && options_.held_odometry_scan_change_m > 0.0 &&
      median_range_change_m(scan, fresh_odometry_ranges_) > options_.held_odometry_scan_change_m) {
    // The pose stays at the held reading's (the stall's start): the next fresh reading's step
    // starts from there.
    out.status = LocalSlamResult::Status::kOdometryStalled;
    record_tracked(scan.stamp_ns, predicted, T_odom_base);
    record_scan(scan.stamp_ns, predicted);
    return out;
  }
  // With odometry the prediction is trusted enough to skip matching near-duplicate scans;
  // without it, every scan is matched (the filter then only gates insertion).
  if (has_odometry && motion_filtered(scan.stamp_ns, predicted)) {
    out.status = LocalSlamResult::Status::kMotionFiltered;
    record_tracked(scan.stamp_ns, predicted, T_odom_base);
    record_scan(scan.stamp_ns, predicted);
    return out;
  }
  std::vector<Eigen::Vector2f> matched_points;
  if (submaps_.empty()) {
    out.status = LocalSlamResult::Status::kFirstScan;
    out.covariance = Covariance3::Identity() * 1e-6;
  } else {
    const SE2 motion = matched_last_ ? matched_last_->second.between(predicted) : SE2();
    const double dist_m = motion.translation().norm();
    const double extra_linear_m = std::min(options_.window_max_extra_linear_m, options_.window_linear_per_m * dist_m);
    const double extra_angular_rad =
        std::min(options_.window_max_extra_angular_rad,
                 options_.window_angular_per_m_rad * dist_m + options_.window_angular_per_rad * std::abs(motion.yaw()));
    matched_points = voxel_filter_2d(points, options_.match_voxel_m);
    out.match =
        matcher_.match(predicted, matched_points, submaps_.matching_submap().grid, extra_linear_m, extra_angular_rad);
    if (!out.match.converged) {
      out.status = LocalSlamResult::Status::kMatchFailed;
      record_tracked(scan.stamp_ns, predicted, T_odom_base);
      record_scan(scan.stamp_ns, predicted);
      return out;
    }
    out.status = LocalSlamResult::Status::kMatched;
    out.pose = out.match.pose;
    out.covariance = out.match.covariance;
  }
  record_tracked(scan.stamp_ns, out.pose, T_odom_base);
  record_matched(scan.stamp_ns, out.pose);
  if (has_odometry || !motion_filtered(scan.stamp_ns, out.pose)) {
    const SubmapInsertion insertion = submaps_.insert(out.pose, points);
    // Covariance weighting of the local constraints: the match's score surface in the submap it was
    // matched against (before insertion changed it little; computed only when enabled).
    Covariance3 shape = Covariance3::Identity();
    const bool shaped =
        options_.loop_closure.local_covariance_weighting && out.status == LocalSlamResult::Status::kMatched;
    if (shaped)
      shape.topLeftCorner<2, 2>() = score_surface_covariance(submaps_.matching_submap().grid, out.pose, matched_points,
                                                             options_.loop_closure.score_surface);
    loop_closure_.add_node(out.pose, points, insertion, submaps_, shaped ? &shape : nullptr);
    out.inserted = true;
    has_inserted_ = true;
    inserted_stamp_ns_ = scan.stamp_ns;
    inserted_pose_ = out.pose;
  }
  record_scan(scan.stamp_ns, out.pose);
  out.T_map_base =
      out.inserted ? loop_closure_.node_pose(loop_closure_.num_nodes() - 1) : loop_closure_.T_global_local() * out.pose;
  return out;
}

}  // namespace cairn::agent
