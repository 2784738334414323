#include "base_station/core/goal_allocator.h"

#include <algorithm>

namespace cairn::base {

bool GoalAllocator::report(const RobotNavReport& report, StampNs now_ns) {
  auto it = orders_.find(report.robot);
  if (it == orders_.end() || it->second.goal_id != report.goal_id || !order_open_[report.robot]) return false;
  const bool ended =
      report.state == NavState::kReached || report.state == NavState::kUnreachable || report.state == NavState::kStuck;
  if (!ended) return false;
  order_open_[report.robot] = false;
  const GoalOrder& order = it->second;
  if (order.kind != GoalKind::kExplore) return true;
  const bool failed = report.state != NavState::kReached;
  const double hold_s = failed ? options_.blacklist_s : options_.reached_blacklist_s;
  blacklisted_.push_back({order.goal_global_m, now_ns + sec_to_ns(hold_s), report.robot, report.state});
  goals_blacklisted_ += failed;
  return true;
}

std::vector<Eigen::Vector2d> GoalAllocator::blacklist_m(StampNs now_ns) const {
  std::vector<Eigen::Vector2d> out;
  for (const BlacklistedGoal& b : blacklisted_) {
    if (b.until_ns > now_ns) out.push_back(b.position_m);
  }
  return out;
}

std::map<RobotId, Eigen::Vector2d> GoalAllocator::current_goals_m() const {
  std::map<RobotId, Eigen::Vector2d> out;
  for (const auto& [robot, order] : orders_) {
    if (order.kind == GoalKind::kExplore && order_open_.at(robot)) out[robot] = order.goal_global_m;
  }
  return out;
}

std::vector<GoalOrder> GoalAllocator::assign(const ExplorationPlan& plan,
                                             const std::map<RobotId, std::optional<SE2>>& placements, StampNs now_ns,
                                             const std::map<RobotId, MeetGoal>& meet) {
  blacklisted_.erase(std::remove_if(blacklisted_.begin(), blacklisted_.end(),
                                    [&](const BlacklistedGoal& b) { return b.until_ns <= now_ns; }),
                     blacklisted_.end());
  // No frontier left that a placed robot can reach: the search is over, everyone placed goes home.
  // (Frontiers behind gaps no robot fits through cannot be explored by this team.) A plan made for
  // no robot (the only placed one is off to a meeting) says nothing of that.
  const bool planned_for_some = !plan.goals.empty() || !plan.idle.empty();
  const bool was_home = sent_home_;
  sent_home_ = planned_for_some && plan.goals.empty();
  if (sent_home_ && !was_home) sent_home_at_ns_ = now_ns;
  std::vector<GoalOrder> changed;
  for (const auto& [robot, placement] : placements) {
    GoalOrder want;
    want.robot = robot;
    const auto meeting = meet.find(robot);
    if (meeting != meet.end()) {
      want.kind = GoalKind::kMeet;
      want.goal_global_m = meeting->second.global_m;
      want.goal_local_m = meeting->second.local_m;
    } else if (!placement) {
      want.kind = GoalKind::kOwn;  // its goal would be in a frame the base cannot place yet
    } else if (sent_home_) {
      want.kind = GoalKind::kHome;
      want.goal_local_m = Eigen::Vector2d::Zero();  // where it entered: its frame's origin
      want.goal_global_m = *placement * want.goal_local_m;
    } else {
      const auto goal = std::find_if(plan.goals.begin(), plan.goals.end(),
                                     [&](const ExplorationGoal& g) { return g.robot == want.robot; });
      if (goal == plan.goals.end()) {
        want.kind = GoalKind::kOwn;  // nothing reachable for it on the merged map
      } else {
        want.kind = GoalKind::kExplore;
        want.goal_global_m = goal->goal_m;
        want.goal_local_m = placement->inverse() * goal->goal_m;
        want.path_m = goal->path_m;
        want.frontier_m = plan.frontiers[size_t(goal->frontier)].length_m;
      }
    }
    auto current = orders_.find(robot);
    if (current != orders_.end() && current->second.kind == want.kind) {
      const GoalOrder& c = current->second;
      const bool open = order_open_[robot];
      const bool same = (c.goal_global_m - want.goal_global_m).norm() < options_.same_goal_m;
      if (want.kind == GoalKind::kOwn || want.kind == GoalKind::kHome) continue;  // nothing new
      if (want.kind == GoalKind::kMeet && same) continue;  // reached or not, the same meeting point
      if (open && same) continue;
    }
    want.goal_id = next_goal_id_++;
    orders_[robot] = want;
    order_open_[robot] = true;
    changed.push_back(want);
  }
  return changed;
}

}  // namespace cairn::base
