#pragma once
// Which goal each robot drives: the base's exploration decisions over time (exploration.h makes one
// plan; this keeps the orders, their ids and what the robots said of them). A goal a robot found
// unreachable or got stuck on is blacklisted for blacklist_s of mission time, so it is never sent
// again at once (the failure explore_lite's users keep reporting: robots that spin at an unreachable
// frontier for ever); so is a goal reached, as its frontier, if it is still there, cannot be resolved.
// Robots the base cannot place yet, or with no frontier left for them while others have one, are
// told to explore their own maps (GoalKind::kOwn), unless they are sent to meet a teammate (kMeet);
// when no linked robot the plan had can reach a frontier any more, every linked robot is sent home. The caller plans
// only once it knows where a placed robot is. Pure: plans and statuses in, orders out.
#include <Eigen/Core>
#include <map>
#include <optional>
#include <vector>

#include "base_station/core/exploration.h"
#include "common/ids.h"
#include "common/navigation.h"
#include "common/se2.h"
#include "common/time.h"

namespace cairn::base {

struct GoalAllocatorOptions {
  double blacklist_s = 300.0;  ///< a failed goal is not sent again for this long
  /// Nor a reached one: a frontier still there once a robot stood on it is one the laser cannot
  /// resolve (a gap in the rubble too small to see through), not worth another trip.
  double reached_blacklist_s = 300.0;
  double blacklist_radius_m = 1.0;  ///< frontier cells this close to a blacklisted goal are skipped
  double same_goal_m = 1.0;         ///< a new plan's goal this close to the current one keeps its id
};

/// What a robot's newest status says of its navigation.
struct RobotNavReport {
  RobotId robot;
  uint32_t goal_id = 0;
  NavState state = NavState::kIdle;
  RobotActivity activity = RobotActivity::kWaiting;
};

/// One robot's order, sent on cairn/goal in its own frame.
struct GoalOrder {
  RobotId robot;
  uint32_t goal_id = 0;
  GoalKind kind = GoalKind::kOwn;
  Eigen::Vector2d goal_global_m{0, 0};  ///< for kExplore and kHome
  Eigen::Vector2d goal_local_m{0, 0};
  double path_m = 0;
  double frontier_m = 0;
};

/// A goal toward a teammate (GoalKind::kMeet), in both frames: the robot's own, and global (for a
/// robot not placed yet, under the guess of its placement).
struct MeetGoal {
  Eigen::Vector2d global_m{0, 0};
  Eigen::Vector2d local_m{0, 0};
};

struct BlacklistedGoal {
  Eigen::Vector2d position_m{0, 0};  ///< global frame
  StampNs until_ns = 0;
  RobotId robot;
  NavState why = NavState::kUnreachable;
};

class GoalAllocator {
 public:
  explicit GoalAllocator(const GoalAllocatorOptions& options = {}) : options_(options) {}

  /// A robot's newest status. A goal of ours it reports unreachable or stuck is blacklisted;
  /// reached or failed, the order is over and the next assign() gives a new one (returns true then).
  bool report(const RobotNavReport& report, StampNs now_ns);

  /// Frontier points the next plan must skip (blacklisted now).
  std::vector<Eigen::Vector2d> blacklist_m(StampNs now_ns) const;
  /// The explore goals being driven (global frame), for the planner's hysteresis.
  std::map<RobotId, Eigen::Vector2d> current_goals_m() const;

  /// New orders from `plan` for every robot: `placements` has every robot the base knows, with
  /// T_global_local for the linked ones. A robot in `meet` drives that goal instead (kMeet: to be
  /// linked, active_linking.h), placed or not. Returns only the orders that changed.
  std::vector<GoalOrder> assign(const ExplorationPlan& plan, const std::map<RobotId, std::optional<SE2>>& placements,
                                StampNs now_ns, const std::map<RobotId, MeetGoal>& meet = {});

  /// `robot` is taken out of the plan (the operator drives it): its order is dropped, so its goal is
  /// free for the others and it gets a fresh order when it is handed back.
  void release(RobotId robot) {
    orders_.erase(robot);
    order_open_.erase(robot);
  }

  const std::map<RobotId, GoalOrder>& orders() const { return orders_; }
  const std::vector<BlacklistedGoal>& blacklisted() const { return blacklisted_; }
  int goals_blacklisted() const { return goals_blacklisted_; }
  bool sent_home() const { return sent_home_; }
  /// When the team was last sent home (mission time); kept when a late frontier calls it back out,
  /// so a report still says the search once ended.
  std::optional<StampNs> sent_home_at_ns() const { return sent_home_at_ns_; }

 private:
  GoalAllocatorOptions options_;
  std::map<RobotId, GoalOrder> orders_;
  std::map<RobotId, bool> order_open_;  ///< false once the robot said the order ended
  std::vector<BlacklistedGoal> blacklisted_;
  uint32_t next_goal_id_ = 1;
  int goals_blacklisted_ = 0;
  bool sent_home_ = false;
  std::optional<StampNs> sent_home_at_ns_;
};

}  // namespace cairn::base
