#pragma once
// What a robot drives to, decided on board (the decisions; navigator.h does the driving). The base
// sends goals (explore this frontier, go home, or "explore on your own" while it cannot place the
// robot); the radio is often cut, so the robot also decides alone (the comms-aware behaviour of the
// DARPA SubT teams):
//   - base goal kExplore (or kMeet, toward a teammate to be linked): drive it; once it is reached or
//     failed, wait base_wait_s for the next one, then take the nearest frontier of the robot's own
//     map until one comes;
//   - kOwn, or no word from the base for autonomy_after_s: the nearest frontier of its own map
//     (failed ones are blacklisted on board); none left: go home;
//   - no word for return_after_s: back to where it last heard the base, then wait there;
//   - kHome, or nothing left on its own map: drive to where it entered (its frame's origin); reached
//     (or failed max_home_attempts times): its mission is over ("done");
//   - its laser lost (on_laser_lost): it cannot see obstacles any more, so it explores no further
//     and drives home by the map it has; the base's goals other than home no longer count.
// Pure: message time in, decisions out; the caller passes the own-frontier search in.
#include <Eigen/Core>
#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "common/navigation.h"
#include "common/time.h"

namespace cairn::agent {

struct MissionBehaviourOptions {
  double base_wait_s = 4.0;        ///< after a base goal ended, wait this long for the next one
  double autonomy_after_s = 15.0;  ///< no word from the base this long: explore on its own
  double return_after_s = 90.0;    ///< no word this long: go back to where it last heard the base
  int max_home_attempts = 3;
  double home_retry_s = 5.0;      ///< a failed drive home is tried again after this (the map may have cleared)
  double home_tolerance_m = 1.0;  ///< home is where it entered, give or take this
  /// A drive home that ends stuck or unreachable this close to home counts as home: the entry is
  /// where the team's robots park, and a parked robot blocks the last metres of another's way.
  double home_area_m = 3.0;
  /// A meeting goal is reached within this, and one in rubble moves to a free cell this near: it is a
  /// guess under the robot's placement hypothesis (an entry hint's sigma is 0.5 m), often a leg's end
  /// on the way (with 0.4 m, a leg's end beside rubble on the collapsed floor ended a meeting).
  double meet_tolerance_m = 1.0;
};

/// A goal for the navigator, in the robot's own frame.
struct DriveTarget {
  uint32_t goal_id = 0;  ///< the base's id; 0 for the robot's own goals
  GoalKind kind = GoalKind::kOwn;
  RobotActivity activity = RobotActivity::kWaiting;
  Eigen::Vector2d position_m{0, 0};
  double tolerance_m = 0;  ///< 0: the navigator's default
};

/// A goal from the base, already in this robot's frame.
struct BaseGoal {
  uint32_t goal_id = 0;
  GoalKind kind = GoalKind::kOwn;
  bool has_goal = false;
  Eigen::Vector2d position_m{0, 0};
};

/// The nearest reachable frontier of the robot's own map from its position, skipping points within
/// the blacklist radius of `blacklist_m`; nullopt when none is left.
using OwnFrontierSearch =
    std::function<std::optional<Eigen::Vector2d>(const std::vector<Eigen::Vector2d>& blacklist_m)>;

class MissionBehaviour {
 public:
  explicit MissionBehaviour(const MissionBehaviourOptions& options = {}) : options_(options) {}

  /// A goal message from the base (also counts as contact).
  void on_base_goal(const BaseGoal& goal, StampNs now_ns, const Eigen::Vector2d& position_m);
  /// Any message from the base: the link works at `position_m`.
  void on_contact(StampNs now_ns, const Eigen::Vector2d& position_m);
  /// The laser is lost for good: home by the map it has, whatever the base says but "home".
  void on_laser_lost() { laser_lost_ = true; }
  bool laser_lost() const { return laser_lost_; }

  /// One decision at a processed scan, the robot at `position_m`. `nav` is the state of the target
  /// last returned (kIdle when none). Returns a new target to drive when it changes; nullopt: keep
  /// driving (or keep still).
  std::optional<DriveTarget> update(StampNs now_ns, const Eigen::Vector2d& position_m, NavState nav,
                                    const OwnFrontierSearch& own_frontier);

  RobotActivity activity() const { return target_ ? target_->activity : idle_activity_; }
  const std::optional<DriveTarget>& target() const { return target_; }
  bool done() const { return idle_activity_ == RobotActivity::kHome && !target_; }
  bool out_of_contact(StampNs now_ns) const;
  /// The reason of the last decision, for the log.
  const std::string& reason() const { return reason_; }

 private:
  std::optional<DriveTarget> choose(StampNs now_ns, const OwnFrontierSearch& own_frontier);
  std::optional<DriveTarget> set(const DriveTarget& target, std::string reason);

  MissionBehaviourOptions options_;
  BaseGoal base_goal_;
  bool base_goal_pending_ = false;   ///< a base goal not driven yet
  StampNs base_goal_ended_ns_ = -1;  ///< when the last base goal ended
  StampNs last_contact_ns_ = -1;
  Eigen::Vector2d contact_position_m_{0, 0};
  std::optional<DriveTarget> target_;
  RobotActivity idle_activity_ = RobotActivity::kWaiting;
  std::vector<Eigen::Vector2d> own_blacklist_m_;
  int home_attempts_ = 0;
  std::optional<DriveTarget> home_retry_;  ///< a failed drive home, tried again at home_retry_at_ns_
  StampNs home_retry_at_ns_ = 0;
  bool waiting_at_contact_point_ = false;
  bool laser_lost_ = false;
  std::string reason_;
};

}  // namespace cairn::agent
