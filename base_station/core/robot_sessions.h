#pragma once
// RobotSessions: which of the base's robots a sample belongs to when robots restart. An agent picks
// a new session id at every start; a robot that rebooted without its state (a new local frame,
// keyframes numbered from 0 again) must not have its new data taken as duplicates of the old, nor
// overwrite what the base acknowledged. So each (robot id, session) the base hears of is a robot of
// its own for the mapper: a robot's first session keeps the robot's id, every later one gets a
// fresh id above every robot id on the wire, is placed by closures like any robot, and is shown as
// "robot 1, session 2". The table, not arithmetic on the id, says whose session it is.
#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "common/ids.h"

namespace cairn::base {

struct RobotSession {
  RobotId base_id;   ///< the robot as the mapper and the console know it
  RobotId robot;     ///< the robot id on the wire (the agent's --robot)
  uint32_t session;  ///< the agent's session id
  int ordinal = 1;   ///< 1 for the first session the base heard of, 2 after one restart, ...
};

class RobotSessions {
 public:
  /// Fresh ids for later sessions start here, above every robot id a sample may carry.
  static constexpr int32_t kFirstRestartId = 1001;

  /// The base's id for `robot`'s `session`; a session not heard of before becomes the robot's
  /// current one (`*is_new` set). Requires a valid robot id below kFirstRestartId.
  RobotId resolve(RobotId robot, uint32_t session, bool* is_new = nullptr);
  /// Puts back a session resolve() made before (from the journal). False when it contradicts one
  /// known (the same base id for another session, or the same session under another base id).
  bool restore(const RobotSession& s);

  std::optional<RobotSession> find(RobotId base_id) const;
  /// True when `base_id` is its robot's newest session (the one the robot runs now): only it gets
  /// acks, corrections, goals and commands. Ids of robots never heard of are current.
  bool is_current(RobotId base_id) const;
  /// The base id of `robot`'s newest session (`robot` itself when none was heard of).
  RobotId current(RobotId robot) const;
  /// "robot1" for a first session, "robot1 session 2" for later ones.
  std::string label(RobotId base_id) const;
  /// Every session after a robot's first, in order.
  std::vector<RobotSession> restarts() const;

 private:
  std::map<RobotId, RobotSession> by_base_id_;
  std::map<RobotId, RobotId> current_;  ///< robot -> base id of its newest session
  int32_t next_restart_id_ = kFirstRestartId;
};

/// The journal's record of a session (JSON), and back; nullopt with `error` naming what is wrong.
std::string session_record_to_json(const RobotSession& s);
std::optional<RobotSession> session_record_from_json(const std::string& text, std::string* error);

}  // namespace cairn::base
