#pragma once
// Follows a planned path with pure pursuit (Coulter 1992): steer along the arc through the path
// point `lookahead_m` further along it, curvature 2 y / d^2 in the robot's frame; rotate on the
// spot first when that point lies more than `turn_in_place_rad` off the heading. Speed ramps down
// over the path's last stretch and as returns ahead come near. The current scan, not the map, is
// the last word: a return the disc would meet within `safety_distance_m` driving on its arc
// stops it (it may still rotate) and asks for a re-plan; returns in the forward corridor (the
// robot's width plus a side margin) slow it down.
// Pure: a path, a pose and a scan in, a command out.
#include <Eigen/Core>
#include <limits>
#include <optional>
#include <vector>

#include "common/laser_scan.h"
#include "common/navigation.h"  // VelocityCommand
#include "common/se2.h"

namespace cairn::agent {

struct PathFollowerOptions {
  double max_speed_mps = 0.5;
  double min_speed_mps = 0.05;  ///< the ramps never ask for less while moving
  double max_turn_radps = 1.0;
  double lookahead_m = 0.6;
  double turn_in_place_rad = 0.8;  ///< heading error above this: rotate on the spot
  double turn_gain = 2.0;          ///< on the spot, angular = gain x heading error (clamped)
  double goal_slowdown_m = 1.0;    ///< speed ramps down linearly over the path's last stretch
  double robot_radius_m = 0.2;
  double safety_distance_m = 0.3;  ///< the disc would meet a return within this driving on: stop
  double side_margin_m = 0.05;     ///< the forward corridor's half width is the radius plus this
  double slow_distance_m = 0.8;    ///< from the edge: returns ahead nearer than this slow it down
  double near_obstacle_m = 0.15;   ///< from the edge: a return this close on any side halves the speed
  double end_reached_m = 0.05;     ///< nearer the path's end than this: stop
  /// Nearer a return than this (from the edge; three standard deviations of a 1 cm ranger) it is
  /// pressed against it: when blocked, it first steps straight away from the returns around it,
  /// at most escape_m and no further than the middle between them, then follows the path again...
  double contact_m = 0.03;
  double escape_m = 0.1;
  double escape_after_s = 2.0;  ///< ... once it has been blocked this long (turning is not driving)
};

struct FollowerOutput {
  VelocityCommand command;
  /// It wanted to move but a return lies within the safety distance ahead: linear speed 0, re-plan.
  bool blocked = false;
  bool escaping = false;  ///< stepping away from returns it is pressed against (see escape_m)
  double obstacle_ahead_m = std::numeric_limits<double>::infinity();  ///< from the front edge
  double remaining_m = 0;  ///< along the path from the robot's projection to its end
  double heading_error_rad = 0;
  Eigen::Vector2d lookahead_m{0, 0};  ///< the pursued point (map frame)
};

/// The fewest of `points` (its ends kept, in order) whose polyline stays within `tolerance_m` of
/// every point dropped: Douglas-Peucker (1973). A grid planner's path of one point per cell becomes
/// its corners, which is what a robot reports of its plan over a slow radio (a status every second).
/// Written here: 25 lines, where Boost.Geometry's simplify would bring a header-only library of
/// its own into the agent's core for this one call.
std::vector<Eigen::Vector2d> simplify_polyline(const std::vector<Eigen::Vector2d>& points, double tolerance_m);

/// The nearest return in the corridor of half width `half_width_m` ahead of the robot (x > 0 in
/// the base frame), as distance from the robot's front edge (x - radius; negative: touching).
double obstacle_ahead_m(const LaserScan& scan, double robot_radius_m, double half_width_m);
/// How far the robot's disc can drive on the arc of `curvature_per_m` (0: straight ahead) before a
/// return enters its front half, checked every 2 cm up to `max_m`; infinity when nothing does.
double free_travel_m(const LaserScan& scan, double robot_radius_m, double curvature_per_m, double max_m);
/// The nearest return in any direction, as distance from the robot's edge.
double nearest_obstacle_m(const LaserScan& scan, double robot_radius_m);
/// The direction (base frame) away from the returns nearer than `within_m` to the centre, each
/// pushing in proportion to how near it is; nullopt when there are none.
std::optional<double> escape_heading_rad(const LaserScan& scan, double within_m);

class PathFollower {
 public:
  explicit PathFollower(const PathFollowerOptions& options = {});

  /// A new path (map frame, the robot's position first); progress starts at its beginning.
  void set_path(std::vector<Eigen::Vector2d> path_m);
  void clear() {
    set_path({});
    escape_.reset();
  }
  const std::vector<Eigen::Vector2d>& path() const { return path_; }
  /// What is left of the path (from the segment the robot is on to the end), simplified to within
  /// `tolerance_m` of it (simplify_polyline) and, if still longer, thinned evenly to at most
  /// `max_points` (>= 2) with its end kept: what the robot reports of its plan.
  std::vector<Eigen::Vector2d> path_ahead(size_t max_points, double tolerance_m = 0.05) const;
  /// The command for the robot at `T_local_base` seeing `scan` (zero without a path).
  FollowerOutput update(const SE2& T_local_base, const LaserScan& scan);
  const PathFollowerOptions& options() const { return options_; }

 private:
  /// Moves progress_ to the segment nearest the robot (never backwards); returns the projection.
  Eigen::Vector2d project(const Eigen::Vector2d& p_m);
  /// The point `distance_m` further along the path from the projection `from` on segment progress_.
  Eigen::Vector2d along(const Eigen::Vector2d& from, double distance_m) const;
  double remaining_from(const Eigen::Vector2d& from) const;
  /// Turning on the spot towards a heading error: gain x error, within the turn limit.
  double turn_rate(double heading_error_rad) const;
  /// Turns to, then drives along, the escape's heading; ends the escape when it has gone escape_m
  /// or cannot drive on.
  void escape_step(const SE2& T_local_base, const LaserScan& scan, FollowerOutput* out);

  /// Where an escape started and the heading it drives (map frame). Kept across re-plans: the
  /// navigator re-plans every half second while blocked.
  struct Escape {
    Eigen::Vector2d from_m;
    double heading_rad = 0;
  };

  PathFollowerOptions options_;
  std::vector<Eigen::Vector2d> path_;
  size_t progress_ = 0;  ///< index of the segment [progress_, progress_ + 1] the robot is on
  std::optional<Escape> escape_;
  std::optional<StampNs> blocked_since_ns_;  ///< stopped for an obstacle since (no drive since)
};

}  // namespace cairn::agent
