#include "base_station/core/active_linking.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <set>

namespace cairn::base {

namespace {

const UnlinkedRobot* find_robot(const std::vector<UnlinkedRobot>& unlinked, RobotId robot) {
  for (const UnlinkedRobot& u : unlinked) {
    if (u.robot == robot) return &u;
  }
  return nullptr;
}

}  // namespace

std::vector<RobotId> ActiveLinker::moving_teammates() const {
  std::vector<RobotId> out;
  for (const auto& [robot, m] : meetings_) {
    if (m.teammate_goal_m) out.push_back(m.teammate);
  }
  return out;
}

std::set<RobotId> ActiveLinker::busy_teammates(RobotId robot) const {
  std::set<RobotId> busy;
  for (const auto& [other, m] : meetings_) {
    if (other != robot && m.teammate_goal_m) busy.insert(m.teammate);
  }
  return busy;
}

MeetingEvent ActiveLinker::fail(RobotId robot, StampNs now_ns, std::string why) {
  MeetingEvent event{MeetingEvent::Kind::kFailed, meetings_.at(robot), std::move(why)};
  not_before_ns_[{robot, meetings_.at(robot).teammate}] = now_ns + sec_to_ns(options_.retry_s);
  meetings_.erase(robot);
  ++stats_.failed;
  return event;
}

std::optional<RobotId> ActiveLinker::choose_teammate(const Eigen::Vector2d& at_m,
                                                     const std::map<RobotId, Eigen::Vector2d>& placed_m, RobotId robot,
                                                     StampNs now_ns) const {
  // The nearest placed robot that no other meeting drives; failing that, the nearest at all (the
  // robot then drives toward it alone). Never one whose meeting with it failed lately.
  const std::set<RobotId> busy = busy_teammates(robot);
  std::optional<RobotId> best, best_free;
  double best_d = std::numeric_limits<double>::infinity(), best_free_d = best_d;
  for (const auto& [id, p] : placed_m) {
    const auto rest = not_before_ns_.find({robot, id});
    if (rest != not_before_ns_.end() && now_ns < rest->second) continue;
    const double d = (p - at_m).norm();
    if (d < best_d) best_d = d, best = id;
    if (!busy.count(id) && d < best_free_d) best_free_d = d, best_free = id;
  }
  return best_free ? best_free : best;
}

void ActiveLinker::set_goals(Meeting* m, const SE2& pose_local,
                             const std::map<RobotId, Eigen::Vector2d>& placed_m) const {
  const Eigen::Vector2d robot_m = m->hypothesis.T_global_local * pose_local.translation();
  const Eigen::Vector2d teammate_m = placed_m.at(m->teammate);
  m->distance_m = (teammate_m - robot_m).norm();
  // They met: the goals stay where they stopped, facing each other (a camera sees the other's
  // marker, the scans overlap) while the linker judges what they saw.
  if (m->met_ns) return;
  m->teammate_goal_m.reset();
  // Each toward the other, stopping short; coincident (distance 0) cannot happen before met_m.
  const Eigen::Vector2d towards_robot = (robot_m - teammate_m) / m->distance_m;
  const double short_m = std::min(options_.stop_short_m, 0.5 * m->distance_m);
  const auto leg = [&](const Eigen::Vector2d& from_m, const Eigen::Vector2d& to_m) -> Eigen::Vector2d {
    const double d = (to_m - from_m).norm();
    return d <= options_.max_leg_m ? to_m : Eigen::Vector2d(from_m + (options_.max_leg_m / d) * (to_m - from_m));
  };
  m->robot_goal_global_m = leg(robot_m, teammate_m + short_m * towards_robot);
  m->robot_goal_local_m = m->hypothesis.T_global_local.inverse() * m->robot_goal_global_m;
  if (options_.move_teammate && !busy_teammates(m->robot).count(m->teammate)) {  // whoever holds it keeps it
    m->teammate_goal_m = leg(teammate_m, robot_m - short_m * towards_robot);
  }
}

std::vector<MeetingEvent> ActiveLinker::update(const std::vector<UnlinkedRobot>& unlinked,
                                               const std::map<RobotId, Eigen::Vector2d>& placed_m, StampNs now_ns,
                                               const LineOfSight& in_sight) {
  const auto together = [&](const Meeting& m, const Eigen::Vector2d& robot_m) {
    return m.distance_m <= options_.met_m && (!in_sight || in_sight(robot_m, placed_m.at(m.teammate)));
  };
  std::vector<MeetingEvent> events;
  if (!options_.enabled) return events;
  // The meetings under way: ended by a link, a timeout or a lost hypothesis; else new goals.
  for (auto it = meetings_.begin(); it != meetings_.end();) {
    Meeting& m = it->second;
    const RobotId robot = it->first;
    ++it;  // fail() erases the current entry
    const UnlinkedRobot* u = find_robot(unlinked, robot);
    if (!u) {
      events.push_back({MeetingEvent::Kind::kLinked, m, ""});
      meetings_.erase(robot);
      ++stats_.linked;
      continue;
    }
    if (!u->hypothesis) {
      events.push_back(fail(robot, now_ns, "its placement hypothesis was withdrawn"));
      continue;
    }
    m.hypothesis = *u->hypothesis;  // the newest (an operator may move it)
    const Eigen::Vector2d at_m = m.hypothesis.T_global_local * u->pose_local.translation();
    const auto nearest = choose_teammate(at_m, placed_m, robot, now_ns);
    if (!placed_m.count(m.teammate)) {
      if (!nearest) {
        events.push_back(fail(robot, now_ns, "no placed teammate is free to meet it"));
        continue;
      }
      m.teammate = *nearest;
    } else if (!m.met_ns && nearest && *nearest != m.teammate &&
               (placed_m.at(*nearest) - at_m).norm() <
                   options_.switch_ratio * (placed_m.at(m.teammate) - at_m).norm()) {
      m.teammate = *nearest;  // a much nearer placed robot: meet that one instead
    }
    if (m.met_ns && ns_to_sec(now_ns - *m.met_ns) > options_.met_wait_s) {
      events.push_back(fail(robot, now_ns, "met, yet nothing they saw verified the link"));
      continue;
    }
    if (!m.met_ns && ns_to_sec(now_ns - m.started_ns) > options_.max_meeting_s) {
      events.push_back(fail(robot, now_ns, "they did not meet in time"));
      continue;
    }
    set_goals(&m, u->pose_local, placed_m);
    if (!m.met_ns && together(m, at_m)) {  // met: both stop where they are, facing each other
      m.met_ns = now_ns;
      m.robot_goal_global_m = at_m;
      m.robot_goal_local_m = u->pose_local.translation();
      if (m.teammate_goal_m) m.teammate_goal_m = placed_m.at(m.teammate);
    }
  }
  // New meetings: robots unlinked for after_s with a hypothesis and a teammate not resting from a
  // failed meeting with it.
  if (placed_m.empty()) return events;
  for (const UnlinkedRobot& u : unlinked) {
    if (meetings_.count(u.robot) || !u.hypothesis) continue;
    if (ns_to_sec(now_ns - u.first_keyframe_ns) < options_.after_s) continue;
    const auto teammate =
        choose_teammate(u.hypothesis->T_global_local * u.pose_local.translation(), placed_m, u.robot, now_ns);
    if (!teammate) continue;
    Meeting m;
    m.robot = u.robot;
    m.teammate = *teammate;
    m.hypothesis = *u.hypothesis;
    m.first_keyframe_ns = u.first_keyframe_ns;
    m.started_ns = now_ns;
    set_goals(&m, u.pose_local, placed_m);
    if (together(m, u.hypothesis->T_global_local * u.pose_local.translation())) continue;  // a meeting adds nothing
    meetings_[u.robot] = m;
    ++stats_.started;
    events.push_back({MeetingEvent::Kind::kStarted, m, ""});
  }
  return events;
}

std::optional<MeetingEvent> ActiveLinker::goal_failed(RobotId robot, StampNs now_ns,
                                                      const std::function<bool(RobotId)>& placed) {
  for (const auto& [unlinked, m] : meetings_) {
    if (placed && placed(unlinked) && (unlinked == robot || m.teammate == robot)) return std::nullopt;
    if (unlinked == robot) return fail(unlinked, now_ns, "it could not drive there");
    if (m.teammate == robot && m.teammate_goal_m) return fail(unlinked, now_ns, "its teammate could not drive there");
  }
  return std::nullopt;
}

}  // namespace cairn::base
