#include "robot_agent/core/navigation/mission_behaviour.h"

namespace cairn::agent {

void MissionBehaviour::on_contact(StampNs now_ns, const Eigen::Vector2d& position_m) {
  last_contact_ns_ = now_ns;
  contact_position_m_ = position_m;
  waiting_at_contact_point_ = false;
}

void MissionBehaviour::on_base_goal(const BaseGoal& goal, StampNs now_ns, const Eigen::Vector2d& position_m) {
  on_contact(now_ns, position_m);
  if (laser_lost_ && goal.kind != GoalKind::kHome) return;                         // it explores no further
  if (goal.goal_id == base_goal_.goal_id && goal.kind == base_goal_.kind) return;  // the same goal, sent again
  base_goal_ = goal;
  base_goal_pending_ = goal.has_goal && goal.kind != GoalKind::kOwn;
}

bool MissionBehaviour::out_of_contact(StampNs now_ns) const {
  return last_contact_ns_ < 0 || ns_to_sec(now_ns - last_contact_ns_) > options_.autonomy_after_s;
}

std::optional<DriveTarget> MissionBehaviour::set(const DriveTarget& target, std::string reason) {
  target_ = target;
  reason_ = std::move(reason);
  return target_;
}

std::optional<DriveTarget> MissionBehaviour::update(StampNs now_ns, const Eigen::Vector2d& position_m, NavState nav,
                                                    const OwnFrontierSearch& own_frontier) {
  const bool ended = nav == NavState::kReached || nav == NavState::kUnreachable || nav == NavState::kStuck;
  if (target_ && !ended) {
    const bool in_contact = !out_of_contact(now_ns);
    const bool lost = last_contact_ns_ >= 0 && ns_to_sec(now_ns - last_contact_ns_) > options_.return_after_s;
    if (base_goal_pending_ && in_contact) return choose(now_ns, own_frontier);  // the base's newer goal first
    if (laser_lost_ && target_->activity != RobotActivity::kGoingHome) return choose(now_ns, own_frontier);
    if (lost && target_->activity != RobotActivity::kReturningToContact &&
        target_->activity != RobotActivity::kGoingHome) {
      return choose(now_ns, own_frontier);
    }
    return std::nullopt;
  }
  if (target_) {
    const DriveTarget done = *target_;
    target_.reset();
    switch (done.activity) {
      case RobotActivity::kExploring:
      case RobotActivity::kMeeting:
        base_goal_ended_ns_ = now_ns;
        break;
      case RobotActivity::kOwnExploration:
        if (nav != NavState::kReached) own_blacklist_m_.push_back(done.position_m);
        break;
      case RobotActivity::kReturningToContact:
        waiting_at_contact_point_ = true;
        break;
      case RobotActivity::kGoingHome:
        if (nav != NavState::kReached && (position_m - done.position_m).norm() <= options_.home_area_m) {
          idle_activity_ = RobotActivity::kHome;
          reason_ = "home: as near as it gets (" + std::to_string(int(100 * (position_m - done.position_m).norm())) +
                    " cm off; the way is blocked, by a parked robot most likely)";
          return std::nullopt;
        }
        if (nav == NavState::kReached || ++home_attempts_ >= options_.max_home_attempts) {
          idle_activity_ = RobotActivity::kHome;
          reason_ = nav == NavState::kReached ? "home" : "gave up reaching home";
          return std::nullopt;
        }
        home_retry_ = done;
        home_retry_at_ns_ = now_ns + sec_to_ns(options_.home_retry_s);
        reason_ = "home not reached yet: trying again soon";
        return std::nullopt;
      default:
        break;
    }
  }
  return choose(now_ns, own_frontier);
}

std::optional<DriveTarget> MissionBehaviour::choose(StampNs now_ns, const OwnFrontierSearch& own_frontier) {
  const bool in_contact = !out_of_contact(now_ns);
  if (base_goal_pending_ && in_contact) {
    base_goal_pending_ = false;
    idle_activity_ = RobotActivity::kWaiting;  // a new goal revives a robot that was home
    home_attempts_ = 0;
    home_retry_.reset();
    DriveTarget t{base_goal_.goal_id, base_goal_.kind, RobotActivity::kExploring, base_goal_.position_m};
    if (base_goal_.kind == GoalKind::kHome) {
      t.activity = RobotActivity::kGoingHome;
      t.tolerance_m = options_.home_tolerance_m;
    }
    if (base_goal_.kind == GoalKind::kMeet) {
      t.activity = RobotActivity::kMeeting;
      t.tolerance_m = options_.meet_tolerance_m;
    }
    return set(t, base_goal_.kind == GoalKind::kHome   ? "the base sends it home"
                  : base_goal_.kind == GoalKind::kMeet ? "the base sends it to meet a teammate"
                                                       : "the base's goal");
  }
  if (idle_activity_ == RobotActivity::kHome) return std::nullopt;  // its mission is over
  if (home_retry_) {
    if (now_ns < home_retry_at_ns_) return std::nullopt;  // waits, then tries home again
    const DriveTarget retry = *home_retry_;
    home_retry_.reset();
    return set(retry, "trying home again");
  }
  if (laser_lost_) {
    return set({0, GoalKind::kOwn, RobotActivity::kGoingHome, Eigen::Vector2d::Zero(), options_.home_tolerance_m},
               "laser lost: it cannot see obstacles any more, home by the map it has");
  }
  const bool lost = last_contact_ns_ >= 0 && ns_to_sec(now_ns - last_contact_ns_) > options_.return_after_s;
  if (lost) {
    if (waiting_at_contact_point_) return std::nullopt;
    return set({0, GoalKind::kOwn, RobotActivity::kReturningToContact, contact_position_m_},
               "out of contact: back to where it last heard the base");
  }
  const bool base_silent_after_goal =
      base_goal_ended_ns_ >= 0 && ns_to_sec(now_ns - base_goal_ended_ns_) > options_.base_wait_s;
  const bool on_its_own = base_goal_.kind == GoalKind::kOwn || !in_contact || base_silent_after_goal;
  if (!on_its_own) {
    target_.reset();
    return std::nullopt;  // waiting for the base's next goal
  }
  if (const auto frontier = own_frontier(own_blacklist_m_)) {
    return set({0, GoalKind::kOwn, RobotActivity::kOwnExploration, *frontier},
               in_contact ? "nearest frontier of its own map" : "out of contact: nearest frontier of its own map");
  }
  return set({0, GoalKind::kOwn, RobotActivity::kGoingHome, Eigen::Vector2d::Zero(), options_.home_tolerance_m},
             "no frontier left on its own map: home");
}

}  // namespace cairn::agent
