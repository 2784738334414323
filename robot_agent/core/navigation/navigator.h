#pragma once
// The robot's navigation core, called once per processed laser scan with the robot's SLAM pose in
// its local frame: the scan goes into the NavMap, the path is (re)planned when needed (a new goal,
// every replan_period_s, and at most every blocked_replan_interval_s while an obstacle ahead stops
// the robot or after a failed plan), the follower turns it into a velocity command and the goal
// tracker (goal_tracker.h) keeps the state: idle, driving, reached, unreachable or stuck, each
// change with its reason. Pure: no DDS, no threads, message time only; the agent's node sends the
// command and publishes the state. The operator's keep-out areas (in the robot's frame) bind every
// plan from the update after they arrive; a goal inside one is unreachable at once.
#include <Eigen/Core>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "common/laser_scan.h"
#include "common/navigation.h"  // VelocityCommand
#include "common/se2.h"
#include "common/time.h"
#include "robot_agent/core/navigation/goal_tracker.h"
#include "robot_agent/core/navigation/nav_map.h"
#include "robot_agent/core/navigation/path_follower.h"
#include "robot_agent/core/navigation/path_planner.h"

namespace cairn::agent {

struct NavGoal {
  uint32_t id = 0;
  Eigen::Vector2d position_m{0, 0};    ///< in the robot's local frame
  GoalKind kind = GoalKind::kExplore;  ///< who asked for it (driven alike; for the log)
  double tolerance_m = 0;              ///< reached within this; <= 0: NavigatorOptions::goal_tolerance_m
  /// Followed when the map shows no path (Breadcrumbs::way, the robot's own steps back), from the
  /// robot's position to the goal; empty: none.
  std::vector<Eigen::Vector2d> fallback_path_m;
  /// > 0 (going home): planned first on the known free space alone, settling for its reachable
  /// point nearest the goal when within this (PathPlanner::plan): a teammate parked at its own entry
  /// across the corridor must not send the robot round the building through unknown space.
  double settle_within_m = 0;
};

struct NavigatorOptions {
  double max_speed_mps = 0.5;
  double max_turn_radps = 1.0;
  double robot_radius_m = 0.2;
  double safety_distance_m = 0.3;  ///< from the robot's edge, ahead
  double lookahead_m = 0.6;
  double goal_tolerance_m = 0.4;
  double replan_period_s = 2.0;
  double stuck_after_s = 10.0;
  double stuck_progress_m = 0.3;
  double unknown_cost = 3.0;  ///< a step through unknown space costs this many times more; 0: never
  /// While stopped by an obstacle ahead, or after a failed plan, re-plan at most this often.
  double blocked_replan_interval_s = 0.5;
  int max_plan_failures = 3;  ///< re-plans failing in a row before the goal is unreachable
  /// Blocked band around walls: robot_radius_m + this (at least half a NavMap cell's diagonal).
  double inflation_margin_m = 0.08;
  NavMapOptions map;
};

/// The components' options as the navigator derives them from its own.
PathPlannerOptions planner_options(const NavigatorOptions& options);
PathFollowerOptions follower_options(const NavigatorOptions& options);
GoalTrackerOptions tracker_options(const NavigatorOptions& options);

struct NavCounters {
  int goals = 0;
  int plans = 0;          ///< every plan made, first ones and re-plans
  int replans = 0;        ///< plans after a goal's first
  int plan_failures = 0;  ///< plans that found no path
  int blocked_stops = 0;  ///< times an obstacle ahead stopped the robot (each stop once)
  int fallbacks = 0;      ///< goals driven along their fallback path (the map showed no way)
};

class Navigator {
 public:
  explicit Navigator(const NavigatorOptions& options = {});

  /// Drives to `goal` from the next update on (replacing any goal).
  void set_goal(const NavGoal& goal);
  /// Stops: idle, no goal.
  void cancel();
  /// The operator's keep-out areas in the robot's frame (replacing any); the path is re-planned.
  void set_keep_out(std::vector<KeepOutPolygon> areas);
  const std::vector<KeepOutPolygon>& keep_out() const { return keep_out_; }
  /// One processed scan at its SLAM pose: maps it, plans if needed, returns the command (zero
  /// unless driving).
  VelocityCommand update(StampNs stamp_ns, const SE2& T_local_base, const LaserScan& scan);

  NavState state() const { return tracker_.state(); }
  const std::optional<NavGoal>& goal() const { return goal_; }
  /// The path being followed (local frame, the robot's position when planned first); for display.
  const std::vector<Eigen::Vector2d>& path() const { return follower_.path(); }
  /// The path still to drive, at most `max_points` (PathFollower::path_ahead); empty without a goal.
  std::vector<Eigen::Vector2d> path_ahead(size_t max_points) const {
    return goal() ? follower_.path_ahead(max_points) : std::vector<Eigen::Vector2d>{};
  }
  /// Why the state last changed.
  const std::string& reason() const { return tracker_.reason(); }
  const NavTransition& last_transition() const { return tracker_.last_transition(); }
  const NavCounters& counters() const { return counters_; }
  const NavMap& map() const { return map_; }
  const PlannedPath& last_plan() const { return last_plan_; }
  const FollowerOutput& last_follow() const { return last_follow_; }
  const NavigatorOptions& options() const { return options_; }

 private:
  double tolerance_m() const;
  /// Plans from `position_m`; false when it failed (the tracker has been told).
  bool replan(StampNs stamp_ns, const Eigen::Vector2d& position_m);

  NavigatorOptions options_;
  NavMap map_;
  PathPlanner planner_;
  PathPlanner known_planner_;  ///< the same on known free space only (NavGoal::settle_within_m)
  PathFollower follower_;
  GoalTracker tracker_;
  std::optional<NavGoal> goal_;
  std::vector<KeepOutPolygon> keep_out_;
  bool keep_out_changed_ = false;  ///< re-plan at the next update
  NavCounters counters_;
  PlannedPath last_plan_;
  FollowerOutput last_follow_;
  bool planned_once_ = false;  ///< a plan was made for the current goal
  bool have_path_ = false;     ///< the last plan succeeded
  bool blocked_ = false;       ///< the last update stopped for an obstacle ahead
  bool on_fallback_ = false;   ///< following the goal's fallback path
  StampNs last_plan_ns_ = 0;
};

}  // namespace cairn::agent
