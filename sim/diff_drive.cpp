#include "sim/diff_drive.h"

#include <algorithm>
#include <cmath>

namespace cairn::sim {

WaypointFollower::WaypointFollower(const Eigen::Vector2d& start_m, std::vector<Eigen::Vector2d> waypoints_m,
                                   const FollowerOptions& options)
    : options_(options), waypoints_(std::move(waypoints_m)), segment_start_(start_m) {}

VelocityCommand WaypointFollower::update(const SE2& T_world_base) {
  const Eigen::Vector2d p = T_world_base.translation();
  while (!finished() && (waypoints_[next_] - p).norm() < options_.waypoint_tolerance_m) {
    segment_start_ = waypoints_[next_];
    ++next_;
  }
  if (finished()) return {};
  const Eigen::Vector2d goal = waypoints_[next_];
  // Carrot: the projection of p on the segment, moved lookahead_m towards the goal.
  const Eigen::Vector2d seg = goal - segment_start_;
  const double seg_len = seg.norm();
  Eigen::Vector2d carrot = goal;
  if (seg_len > 1e-9) {
    const Eigen::Vector2d u = seg / seg_len;
    const double s = std::clamp((p - segment_start_).dot(u), 0.0, seg_len);
    carrot = segment_start_ + std::min(seg_len, s + options_.lookahead_m) * u;
  }
  const Eigen::Vector2d to_carrot = carrot - p;
  const double heading_error = normalize_angle(std::atan2(to_carrot.y(), to_carrot.x()) - T_world_base.yaw());
  VelocityCommand cmd;
  cmd.angular_radps =
      std::clamp(options_.heading_gain * heading_error, -options_.max_turn_radps, options_.max_turn_radps);
  if (std::abs(heading_error) < options_.turn_in_place_rad) {
    double v = options_.max_speed_mps * std::cos(heading_error);
    if (next_ + 1 == waypoints_.size()) {
      v = std::min(v, options_.stop_gain * (goal - p).norm() + 0.05);
    }
    cmd.linear_mps = std::max(0.0, v);
  }
  return cmd;
}

SE2 integrate_unicycle(const SE2& T_world_base, double linear_mps, double angular_radps, double dt_s) {
  const double dyaw = angular_radps * dt_s;
  const double d = linear_mps * dt_s;
  Eigen::Vector2d t_base;
  if (std::abs(dyaw) < 1e-9) {
    t_base = Eigen::Vector2d(d, 0.0);
  } else {
    const double r = d / dyaw;  // arc radius
    t_base = Eigen::Vector2d(r * std::sin(dyaw), r * (1.0 - std::cos(dyaw)));
  }
  return T_world_base * SE2(t_base, dyaw);
}

OdometryIntegrator::OdometryIntegrator(const OdometryOptions& options, uint64_t seed) : options_(options), rng_(seed) {}

void OdometryIntegrator::add_step(const SE2& delta_true, double dt_s) {
  const double d = delta_true.translation().norm();
  const double rot = std::abs(delta_true.yaw());
  const double sd_trans = options_.trans_noise_per_m * std::sqrt(d);
  const double var_rot = options_.rot_noise_rad_per_m * options_.rot_noise_rad_per_m * d +
                         options_.rot_noise_per_rad * options_.rot_noise_per_rad * rot;
  std::normal_distribution<double> unit(0.0, 1.0);
  // Draw all three every step so the random stream does not depend on the motion.
  const double n_along = unit(rng_), n_across = unit(rng_), n_rot = unit(rng_);
  Eigen::Vector2d t = delta_true.translation();
  if (d > 1e-12) {
    const Eigen::Vector2d u = t / d;
    const Eigen::Vector2d n(-u.y(), u.x());
    // Most wheel error is along the motion; a smaller part (slip) is lateral.
    t += sd_trans * n_along * u + 0.3 * sd_trans * n_across * n;
  }
  const SE2 delta_noisy(t, delta_true.yaw() + std::sqrt(var_rot) * n_rot);
  T_odom_base_ = T_odom_base_ * delta_noisy;
  if (dt_s > 0) {
    linear_mps_ = delta_noisy.translation().x() / dt_s;
    angular_radps_ = delta_noisy.yaw() / dt_s;
  }
}

}  // namespace cairn::sim
