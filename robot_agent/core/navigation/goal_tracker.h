#pragma once
// The goal's state machine:
//
//   idle --start--> driving --within tolerance----------------------------> reached
//                      |  ---no path for a new goal, or max_plan_failures
//                      |     re-plans failed in a row-------------------------> unreachable
//                      |  ---moved less than stuck_progress_m in the last
//                      |     stuck_after_s seconds of message time-------------> stuck
//                      |  ---stayed within confined_radius_m for the last
//                      |     confined_after_s (back and forth: a livelock)-----> stuck
//   any --cancel--> idle;  any --start (a new goal)--> driving
//
// Every change carries a reason. Progress is the robot's displacement from where it last was
// stuck_progress_m away from (turning on the spot is no progress). A robot that swings back and forth
// (blocked, steps away, re-plans into the same block) makes that kind of progress for ever: seen in
// the office, 0.85 m to and fro for 40 s while going home. Hence the second, longer test on the
// area it stays in. A failed plan that finds the
// robot boxed in (no way out of its immediate surroundings) does not count towards unreachable:
// the goal may be fine, the robot cannot move; that ends in stuck. Pure: message time only.
#include <Eigen/Core>
#include <deque>
#include <optional>
#include <string>
#include <utility>

#include "common/navigation.h"  // NavState
#include "common/time.h"

namespace cairn::agent {

struct GoalTrackerOptions {
  double stuck_after_s = 10.0;
  double stuck_progress_m = 0.3;
  int max_plan_failures = 3;  ///< re-plans failing in a row (not boxed in) before unreachable
  double confined_after_s = 30.0;
  double confined_radius_m = 1.0;  ///< every pose of the last confined_after_s within this of their mean
};

struct NavTransition {
  NavState from = NavState::kIdle;
  NavState to = NavState::kIdle;
  StampNs stamp_ns = 0;  ///< message time of the change (the last stamp seen)
  std::string reason;
};

class GoalTracker {
 public:
  explicit GoalTracker(const GoalTrackerOptions& options = {});

  /// A new goal: driving; progress and failures start afresh.
  void start(const std::string& reason);
  void cancel(const std::string& reason);
  /// The robot at `position_m` at `stamp_ns`, while driving: may turn to stuck. Stamps must not go
  /// backwards (an older one is ignored).
  void note_pose(StampNs stamp_ns, const Eigen::Vector2d& position_m);
  /// Within tolerance at `stamp_ns`: reached (even when the stuck timer would fire at that stamp).
  void reached(StampNs stamp_ns, const std::string& reason);
  /// A plan succeeded: the failure count restarts, the robot is not boxed in.
  void plan_succeeded();
  /// A plan failed. The first plan of a goal failing, or max_plan_failures in a row, make it
  /// unreachable; a boxed-in robot is left to the stuck timer (its reason is kept for it).
  void plan_failed(bool first_plan, bool boxed_in, const std::string& why);

  NavState state() const { return state_; }
  const std::string& reason() const { return last_.reason; }
  const NavTransition& last_transition() const { return last_; }
  int transitions() const { return transitions_; }
  int consecutive_failures() const { return failures_; }
  /// Seconds since the robot last made stuck_progress_m of progress (0 before the first pose).
  double seconds_without_progress() const;

 private:
  void change(NavState to, const std::string& reason);

  GoalTrackerOptions options_;
  NavState state_ = NavState::kIdle;
  NavTransition last_;
  int transitions_ = 0;
  int failures_ = 0;
  std::string boxed_in_;  ///< why the last plan found the robot boxed in (empty: it did not)
  StampNs stamp_ns_ = 0;  ///< the newest stamp seen
  std::optional<StampNs> anchor_stamp_ns_;
  Eigen::Vector2d anchor_m_{0, 0};
  /// Poses of the last confined_after_s (and the one just before), oldest first.
  std::deque<std::pair<StampNs, Eigen::Vector2d>> recent_;
  /// Stuck with a reason when every pose of the last confined_after_s stayed in a small disc.
  bool confined();
};

}  // namespace cairn::agent
