#pragma once
// The simulator's command side: each robot's cairn/robot<N>/cmd_vel reader. In lock-step the
// simulator waits, after a step that carried laser scans, until every robot's agent answered its
// scan with a command stamped at (or after) it, so a mission's motion does not depend on how fast
// the processes run; a robot whose agent stays silent for `timeout_s` is driven with a zero command
// and no longer waited for until it answers again.
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "common/logging.h"
#include "common/navigation.h"
#include "dds/endpoints.h"

namespace cairn::sim {

class SimCommands {
 public:
  static std::unique_ptr<SimCommands> create(dds::Participant& participant, const std::vector<RobotId>& robots,
                                             std::string* error);
  /// Takes every command that arrived (the newest per robot is kept).
  void poll();
  /// Polls until the newest command of every responsive robot of `scanned` (those whose laser
  /// scanned at stamp_ns: a robot with a broken laser is not waited for) has stamp >= stamp_ns, or
  /// timeout_s.
  void wait_for_answers(StampNs stamp_ns, const std::vector<RobotId>& scanned, double timeout_s);
  /// The newest valid command of `robot` (zero, not done, before the first one).
  const StampedCommand& latest(RobotId robot) const { return latest_.at(robot); }
  int bad_commands() const { return bad_; }

 private:
  SimCommands() = default;
  std::map<RobotId, std::unique_ptr<dds::Reader<dds::CmdVelTopic>>> readers_;
  std::map<RobotId, StampedCommand> latest_;
  std::map<RobotId, bool> silent_;  ///< timed out once: not waited for until it answers again
  int bad_ = 0;
  std::shared_ptr<spdlog::logger> log_ = make_logger("sim");
};

}  // namespace cairn::sim
