#include "robot_agent/core/navigation/navigator.h"

#include <algorithm>
#include <cstdio>

#include "common/check.h"

namespace cairn::agent {
namespace {

/// Within this of a goal the planner had to move (its own cell was blocked): reached as near as
/// the robot can get.
constexpr double kMovedGoalReachedM = 0.1;

std::string describe(const NavGoal& goal) {
  char buf[96];
  std::snprintf(buf, sizeof(buf), "goal %u (%s) at (%.2f, %.2f)", goal.id, to_string(goal.kind), goal.position_m.x(),
                goal.position_m.y());
  return buf;
}

}  // namespace

PathPlannerOptions planner_options(const NavigatorOptions& o) {
  PathPlannerOptions p;
  p.robot_radius_m = o.robot_radius_m;
  p.inflation_margin_m = o.inflation_margin_m;
  p.unknown_cost = o.unknown_cost;
  return p;
}

PathFollowerOptions follower_options(const NavigatorOptions& o) {
  PathFollowerOptions f;
  f.max_speed_mps = o.max_speed_mps;
  f.max_turn_radps = o.max_turn_radps;
  f.lookahead_m = o.lookahead_m;
  f.robot_radius_m = o.robot_radius_m;
  f.safety_distance_m = o.safety_distance_m;
  f.slow_distance_m = std::max(f.slow_distance_m, o.safety_distance_m + 0.2);
  return f;
}

GoalTrackerOptions tracker_options(const NavigatorOptions& o) {
  GoalTrackerOptions t;
  t.stuck_after_s = o.stuck_after_s;
  t.stuck_progress_m = o.stuck_progress_m;
  t.max_plan_failures = o.max_plan_failures;
  return t;
}

Navigator::Navigator(const NavigatorOptions& options)
    : options_(options),
      map_(options.map),
      planner_(planner_options(options)),
      known_planner_([&] {
        PathPlannerOptions known = planner_options(options);
        known.unknown_cost = 0;
        return known;
      }()),
      follower_(follower_options(options)),
      tracker_(tracker_options(options)) {}

double Navigator::tolerance_m() const {
  return goal_ && goal_->tolerance_m > 0 ? goal_->tolerance_m : options_.goal_tolerance_m;
}

void Navigator::set_goal(const NavGoal& goal) {
  const std::string reason = goal_ && tracker_.state() == NavState::kDriving
                                 ? describe(goal) + " replaces " + describe(*goal_)
                                 : describe(goal);
  goal_ = goal;
  ++counters_.goals;
  planned_once_ = have_path_ = blocked_ = on_fallback_ = false;
  follower_.clear();
  last_plan_ = PlannedPath{};
  tracker_.start(reason);
}

void Navigator::cancel() {
  if (goal_) tracker_.cancel("cancelled " + describe(*goal_));
  goal_.reset();
  have_path_ = blocked_ = on_fallback_ = false;
  follower_.clear();
}

void Navigator::set_keep_out(std::vector<KeepOutPolygon> areas) {
  keep_out_ = std::move(areas);
  keep_out_changed_ = true;
}

bool Navigator::replan(StampNs stamp_ns, const Eigen::Vector2d& position_m) {
  CAIRN_CHECK(goal_.has_value(), "planning without a goal");
  keep_out_changed_ = false;
  if (goal_->settle_within_m > 0) {
    last_plan_ =
        known_planner_.plan(map_, position_m, goal_->position_m, tolerance_m(), keep_out_, goal_->settle_within_m);
  }
  if (goal_->settle_within_m <= 0 || !last_plan_.ok()) {
    last_plan_ = planner_.plan(map_, position_m, goal_->position_m, tolerance_m(), keep_out_);
  }
  ++counters_.plans;
  if (planned_once_) ++counters_.replans;
  const bool first = !planned_once_;
  planned_once_ = true;
  last_plan_ns_ = stamp_ns;
  have_path_ = last_plan_.ok();
  if (!have_path_ && !goal_->fallback_path_m.empty()) {
    // No way on the map: the fallback (the robot's own steps), kept, not restarted, at each failed
    // re-plan; the laser's safety stop still guards it, and the stuck timer still ends it.
    if (!on_fallback_) {
      follower_.set_path(goal_->fallback_path_m);
      ++counters_.fallbacks;
      on_fallback_ = true;
    }
    have_path_ = true;
    tracker_.plan_succeeded();
    return true;
  }
  on_fallback_ = false;
  if (!have_path_) {
    ++counters_.plan_failures;
    follower_.clear();
    // A goal in a keep-out area stays there: unreachable at once, like a first plan that failed.
    const bool final = first || last_plan_.status == PlanStatus::kGoalKeptOut;
    tracker_.plan_failed(final, last_plan_.boxed_in, describe(*goal_) + ": " + last_plan_.reason);
    return false;
  }
  tracker_.plan_succeeded();
  follower_.set_path(last_plan_.path_m);
  return true;
}

VelocityCommand Navigator::update(StampNs stamp_ns, const SE2& T_local_base, const LaserScan& scan) {
  map_.insert(T_local_base, scan);
  last_follow_ = FollowerOutput{};
  if (tracker_.state() != NavState::kDriving) return {};
  const Eigen::Vector2d position = T_local_base.translation();
  char buf[96];
  const double to_goal_m = (position - goal_->position_m).norm();
  const bool moved_goal = have_path_ && last_plan_.goal_m != goal_->position_m;
  // A point settled for short of an unreachable goal lies by the obstacle, nearer than the laser's
  // safety stop lets the robot go (safety_distance_m from its edge): that near is as near as it gets.
  const double moved_reach_m =
      last_plan_.settled ? options_.robot_radius_m + options_.safety_distance_m : kMovedGoalReachedM;
  if (to_goal_m <= tolerance_m() || (moved_goal && (position - last_plan_.goal_m).norm() <= moved_reach_m)) {
    std::snprintf(buf, sizeof(buf), ": %.2f m from it (tolerance %.2f m)%s", to_goal_m, tolerance_m(),
                  to_goal_m <= tolerance_m() ? "" : ", as near as its free space allows");
    tracker_.reached(stamp_ns, describe(*goal_) + buf);
    follower_.clear();
    return {};
  }
  tracker_.note_pose(stamp_ns, position);
  if (tracker_.state() != NavState::kDriving) {  // stuck
    follower_.clear();
    return {};
  }
  const double since_plan_s = ns_to_sec(stamp_ns - last_plan_ns_);
  const bool due = !planned_once_ || keep_out_changed_ || since_plan_s >= options_.replan_period_s ||
                   ((blocked_ || !have_path_) && since_plan_s >= options_.blocked_replan_interval_s);
  if (due && !replan(stamp_ns, position)) return {};
  if (!have_path_) return {};  // waiting to retry a failed plan
  last_follow_ = follower_.update(T_local_base, scan);
  if (last_follow_.blocked && !blocked_) ++counters_.blocked_stops;
  blocked_ = last_follow_.blocked;
  return last_follow_.command;
}

}  // namespace cairn::agent
