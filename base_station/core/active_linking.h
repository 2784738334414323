#pragma once
// Active linking: a robot the base has not placed after after_s is sent to meet a placed teammate,
// so that the overlap of their scans, or one seeing the other's marker, links it soon. Where to meet
// needs a guess of where the robot is: a hypothesis of its placement (an entry hint, or the
// operator's alignment still being judged). Under it, each of the two drives toward the other and
// stops stop_short_m before it; they have met when within met_m with no wall between them, and
// then stop where they are (facing each other) until the link comes or met_wait_s passes; the teammate drives only
// while it is the nearest placed robot not meeting another. A hypothesis is never a link: the linker's verification
// alone decides. A meeting that brings no link (the guess was wrong, or the place looks like many others) is given up
// and the pair is not sent to meet again for retry_s (the robot may meet another teammate meanwhile, or explore its own
// map, as before). A meeting switches to a placed robot much nearer than its teammate (one linked since, often on the
// way). A robot with no hypothesis is not sent anywhere: without one, "toward the others" has no direction in its own
// frame. Pure: positions and hypotheses in, meetings out; the class keeps the meetings over time.
#include <Eigen/Core>
#include <functional>
#include <map>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "common/ids.h"
#include "common/se2.h"
#include "common/time.h"

namespace cairn::base {

struct ActiveLinkingOptions {
  bool enabled = true;
  double after_s = 5.0;       ///< not linked this long after its first keyframe (mission time): sent to meet
  double stop_short_m = 1.5;  ///< each drives to this far short of the other: they must not collide
  /// Each goal lies at most this far from its robot, toward the other (the goals follow as they
  /// drive): a robot plans on its own map, and refuses a goal far outside it.
  double max_leg_m = 10.0;
  double met_m = 3.0;           ///< this close under the hypothesis, in sight: they met, the link should follow
  double met_wait_s = 15.0;     ///< met and still not linked this long after: the meeting failed
  double max_meeting_s = 90.0;  ///< nor met after this long: the meeting failed
  double retry_s = 60.0;        ///< a pair whose meeting failed is not sent to meet again for this long
  /// A meeting switches to another placed robot nearer than this share of the distance to its
  /// teammate (one placed since, or one the robot drove toward).
  double switch_ratio = 0.6;
  bool move_teammate = true;  ///< the teammate drives toward it too (they meet in half the time)
};

/// A guess of an unlinked robot's placement, never a link.
struct LinkHypothesis {
  SE2 T_global_local;
  std::string source;  ///< "entry hint", "operator alignment"
};

/// A robot not on the map yet that has sent at least one keyframe (mission time may start at 0).
struct UnlinkedRobot {
  RobotId robot;
  StampNs first_keyframe_ns = 0;  ///< its first keyframe's stamp
  SE2 pose_local;                 ///< its newest pose, own frame
  std::optional<LinkHypothesis> hypothesis;
};

struct Meeting {
  RobotId robot;     ///< not linked yet
  RobotId teammate;  ///< placed
  LinkHypothesis hypothesis;
  StampNs first_keyframe_ns = 0;  ///< the robot's
  StampNs started_ns = 0;
  std::optional<StampNs> met_ns;
  double distance_m = 0;                      ///< between the two, under the hypothesis
  Eigen::Vector2d robot_goal_local_m{0, 0};   ///< in the robot's own frame
  Eigen::Vector2d robot_goal_global_m{0, 0};  ///< the same, under the hypothesis
  /// The teammate's goal (global frame); none when it keeps exploring (another meeting holds it, or
  /// move_teammate is off).
  std::optional<Eigen::Vector2d> teammate_goal_m;
};

/// Whether a robot at a could see one at b (no wall between them on the global map).
using LineOfSight = std::function<bool(const Eigen::Vector2d& a_m, const Eigen::Vector2d& b_m)>;

/// What changed at an update, for the log and the results.
struct MeetingEvent {
  enum class Kind { kStarted, kLinked, kFailed } kind = Kind::kStarted;
  Meeting meeting;
  std::string why;  ///< kFailed: the reason
};

struct ActiveLinkingStats {
  int started = 0;
  int linked = 0;  ///< meetings that ended with the robot linked
  int failed = 0;
};

class ActiveLinker {
 public:
  explicit ActiveLinker(const ActiveLinkingOptions& options = {}) : options_(options) {}

  /// One decision at mission time now_ns: `unlinked` are the robots not placed yet, `placed_m` the
  /// placed robots the planner may send (global positions); `in_sight` (none: always) tells
  /// whether two close robots can see each other, for they have met only then. Returns what
  /// changed; meetings() then holds the meetings to drive.
  std::vector<MeetingEvent> update(const std::vector<UnlinkedRobot>& unlinked,
                                   const std::map<RobotId, Eigen::Vector2d>& placed_m, StampNs now_ns,
                                   const LineOfSight& in_sight = {});
  /// The goal of a meeting ended unreachable or stuck for `robot` (either side): the meeting fails,
  /// unless its unlinked robot is `placed` by now (linked since the last update(), which then
  /// reports the meeting linked: a robot may give up its goal in the same second it was linked).
  std::optional<MeetingEvent> goal_failed(RobotId robot, StampNs now_ns,
                                          const std::function<bool(RobotId)>& placed = {});

  const std::map<RobotId, Meeting>& meetings() const { return meetings_; }  ///< by the unlinked robot
  /// The teammates driving to a meeting: the planner leaves them out.
  std::vector<RobotId> moving_teammates() const;
  const ActiveLinkingStats& stats() const { return stats_; }
  const ActiveLinkingOptions& options() const { return options_; }

 private:
  MeetingEvent fail(RobotId robot, StampNs now_ns, std::string why);
  /// The teammates other meetings than `robot`'s drive (one meeting at a time each).
  std::set<RobotId> busy_teammates(RobotId robot) const;
  std::optional<RobotId> choose_teammate(const Eigen::Vector2d& at_m,
                                         const std::map<RobotId, Eigen::Vector2d>& placed_m, RobotId robot,
                                         StampNs now_ns) const;
  void set_goals(Meeting* meeting, const SE2& pose_local, const std::map<RobotId, Eigen::Vector2d>& placed_m) const;

  ActiveLinkingOptions options_;
  std::map<RobotId, Meeting> meetings_;
  /// (robot, teammate) -> not sent to meet before: after their meeting failed.
  std::map<std::pair<RobotId, RobotId>, StampNs> not_before_ns_;
  ActiveLinkingStats stats_;
};

}  // namespace cairn::base
