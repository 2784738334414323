#pragma once
// The operator's commands at the base (the control centre's "drive there, stop, resume, home"):
// check_command() decides whether a request from the console may be sent at all, CommandBook keeps
// every command sent and what became of it. A command's life: sent (on cairn/operator_command,
// newest per robot) -> acknowledged, active, done, refused or failed, as the robot reports in its
// status -> or overtaken, when the robot reports a newer command first (keep-last-1 delivery means
// an overtaken command may never have reached it). Sequence numbers grow over the whole mission and
// survive a base restart (the journal holds every command).
// Pure: requests, placements and robots' reports in; records out.
#include <Eigen/Core>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "base_station/core/search_controls.h"
#include "common/ids.h"
#include "common/navigation.h"
#include "common/se2.h"
#include "common/time.h"

namespace cairn::base {

/// One request from the console, already parsed.
struct CommandRequest {
  std::vector<RobotId> robots;  ///< the robots it goes to ("all": every robot the base knows)
  CommandKind kind = CommandKind::kStop;
  Eigen::Vector2d point_global_m{0, 0};  ///< kGoTo: where, in the merged map's frame
};

/// What the base knows when it checks a request.
struct CommandCheckContext {
  std::map<RobotId, std::optional<SE2>> placements;  ///< every robot known; T_global_local once linked
  bool has_map = false;
  Eigen::Vector2d map_min_m{0, 0};  ///< the merged map's extent (global frame)
  Eigen::Vector2d map_max_m{0, 0};
  std::vector<KeepOutArea> keep_out;  ///< the operator's: no goto into them
  bool exploration_paused = false;    ///< a robot is not resumed while the search is paused
  /// Robots' sessions that ended (RobotSessions: the robot restarted since), with the id of the
  /// session it runs now: a command goes to that one.
  std::map<RobotId, RobotId> ended_sessions;
};

/// Why `request` must not be sent (no robot, an unknown robot, a goto to a robot not placed on the
/// map yet, a point that is not finite, outside the map or in a keep-out area, a resume while the
/// exploration is paused); nullopt when it may go.
std::optional<std::string> check_command(const CommandRequest& request, const CommandCheckContext& context);

/// One command sent to one robot.
struct CommandRecord {
  uint32_t seq = 0;
  RobotId robot;
  CommandKind kind = CommandKind::kStop;
  Eigen::Vector2d point_global_m{0, 0};  ///< kGoTo
  Eigen::Vector2d point_local_m{0, 0};   ///< the same point in the robot's own frame (what was sent)
  StampNs sent_ns = 0;                   ///< mission time
  CommandState state = CommandState::kSent;
  std::string note;
};

class CommandBook {
 public:
  /// Records a command and returns the message to send. `T_global_local` places the robot (needed
  /// for kGoTo; check_command() made sure it is known). `seq` must be larger than every seq so far.
  OperatorCommand add(uint32_t seq, RobotId robot, CommandKind kind, const Eigen::Vector2d& point_global_m,
                      const std::optional<SE2>& T_global_local, StampNs now_ns);
  /// A command read back from the journal (after a base restart), as it was sent.
  void restore(const OperatorCommand& sent, const Eigen::Vector2d& point_global_m, StampNs sent_ns);
  /// A robot's word on its newest command. Returns true when a record changed.
  bool on_report(RobotId robot, const CommandReport& report);

  /// The operator, not the exploration planner, decides where `robot` goes: its newest command is
  /// goto, stop or home (not resume).
  bool under_operator(RobotId robot) const;
  /// The kind of the newest command sent to `robot`, if any.
  std::optional<CommandKind> newest_kind(RobotId robot) const;
  const std::vector<CommandRecord>& records() const { return records_; }
  uint32_t last_seq() const { return records_.empty() ? 0 : records_.back().seq; }

 private:
  CommandRecord* find(uint32_t seq);
  std::vector<CommandRecord> records_;  ///< by seq, ascending
};

}  // namespace cairn::base
