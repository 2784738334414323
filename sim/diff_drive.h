#pragma once
// Differential-drive robot motion for the simulator: a waypoint follower (pure pursuit on the
// current route segment, turning in place when the heading error is large), exact unicycle
// integration of the commanded velocities, and a noisy wheel-odometry integrator.
#include <Eigen/Core>
#include <random>
#include <vector>

#include "common/navigation.h"  // VelocityCommand
#include "common/se2.h"
#include "sim/sim_options.h"

namespace cairn::sim {

struct FollowerOptions {
  double max_speed_mps = 0.6;
  double max_turn_radps = 1.2;
  double lookahead_m = 0.4;           ///< pure-pursuit carrot distance along the segment
  double waypoint_tolerance_m = 0.1;  ///< a waypoint is reached within this distance
  double turn_in_place_rad = 0.6;     ///< heading errors above this rotate without moving
  double heading_gain = 2.5;          ///< angular_radps per rad of heading error
  double stop_gain = 1.0;             ///< speed limit near the final waypoint: gain * distance
};

/// Drives a robot through its waypoints in order and stops at the last one. Tracks the segment
/// from the previous waypoint (the start position for the first) so the robot stays on the route.
class WaypointFollower {
 public:
  WaypointFollower(const Eigen::Vector2d& start_m, std::vector<Eigen::Vector2d> waypoints_m,
                   const FollowerOptions& options);
  /// Advances past reached waypoints and returns the command for the current pose.
  VelocityCommand update(const SE2& T_world_base);
  bool finished() const { return next_ >= waypoints_.size(); }
  size_t next_waypoint() const { return next_; }

 private:
  FollowerOptions options_;
  std::vector<Eigen::Vector2d> waypoints_;
  Eigen::Vector2d segment_start_;
  size_t next_ = 0;
};

/// Exact integration of constant (v, w) over dt (arc of a circle; straight line when w = 0).
SE2 integrate_unicycle(const SE2& T_world_base, double linear_mps, double angular_radps, double dt_s);

/// Wheel odometry: composes each true step motion corrupted by Gaussian noise (see OdometryOptions
/// for the noise model) into T_odom_base, the odom frame being the robot's start pose.
class OdometryIntegrator {
 public:
  OdometryIntegrator(const OdometryOptions& options, uint64_t seed);
  /// Adds one step; `delta_true` is the true motion in the base frame at the step start.
  void add_step(const SE2& delta_true, double dt_s);
  const SE2& T_odom_base() const { return T_odom_base_; }
  double linear_mps() const { return linear_mps_; }
  double angular_radps() const { return angular_radps_; }

 private:
  OdometryOptions options_;
  std::mt19937_64 rng_;
  SE2 T_odom_base_;
  double linear_mps_ = 0.0;
  double angular_radps_ = 0.0;
};

}  // namespace cairn::sim
