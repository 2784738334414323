#include "base_station/core/operator_commands.h"

#include <algorithm>
#include <cmath>

#include "common/check.h"

namespace cairn::base {

std::optional<std::string> check_command(const CommandRequest& request, const CommandCheckContext& context) {
  if (request.robots.empty()) return "no robot: the base has not heard of any robot yet";
  for (RobotId robot : request.robots) {
    const auto it = context.placements.find(robot);
    if (it == context.placements.end()) return "unknown robot " + std::to_string(robot.value);
    if (const auto ended = context.ended_sessions.find(robot); ended != context.ended_sessions.end()) {
      return "robot " + std::to_string(robot.value) + " is a session that ended (the robot restarted): command " +
             std::to_string(ended->second.value) + ", the session it runs now";
    }
    if (request.kind == CommandKind::kGoTo && !it->second) {
      return "robot " + std::to_string(robot.value) +
             " is not placed on the map yet: a point on the map means nothing to it (stop, resume and home work)";
    }
  }
  if (request.kind == CommandKind::kResume && context.exploration_paused)
    return "exploration is paused: resume the exploration first (goto, stop and home work)";
  if (request.kind != CommandKind::kGoTo) return std::nullopt;
  const Eigen::Vector2d& p = request.point_global_m;
  if (!std::isfinite(p.x()) || !std::isfinite(p.y())) return "the point is not a finite number";
  if (!context.has_map) return "there is no map yet to send a robot to";
  if ((p.array() < context.map_min_m.array()).any() || (p.array() > context.map_max_m.array()).any()) {
    char buf[200];
    std::snprintf(buf, sizeof buf, "the point (%.6g, %.6g) m is outside the map ([%.1f, %.1f] x [%.1f, %.1f] m)", p.x(),
                  p.y(), context.map_min_m.x(), context.map_max_m.x(), context.map_min_m.y(), context.map_max_m.y());
    return std::string(buf);
  }
  for (const KeepOutArea& area : context.keep_out)
    if (area.contains(p)) return "the point is in keep-out area " + std::to_string(area.id);
  return std::nullopt;
}

OperatorCommand CommandBook::add(uint32_t seq, RobotId robot, CommandKind kind, const Eigen::Vector2d& point_global_m,
                                 const std::optional<SE2>& T_global_local, StampNs now_ns) {
  CAIRN_CHECK(seq > last_seq(), "operator command seq " + std::to_string(seq) + " after " + std::to_string(last_seq()));
  CAIRN_CHECK(kind != CommandKind::kGoTo || T_global_local.has_value(), "a goto to a robot that is not placed");
  CommandRecord r;
  r.seq = seq;
  r.robot = robot;
  r.kind = kind;
  r.sent_ns = now_ns;
  if (kind == CommandKind::kGoTo) {
    r.point_global_m = point_global_m;
    r.point_local_m = T_global_local->inverse() * point_global_m;
  }
  records_.push_back(r);
  return {robot, seq, kind, r.point_local_m};
}

void CommandBook::restore(const OperatorCommand& sent, const Eigen::Vector2d& point_global_m, StampNs sent_ns) {
  if (find(sent.seq)) return;
  CommandRecord r;
  r.seq = sent.seq;
  r.robot = sent.robot;
  r.kind = sent.kind;
  r.point_global_m = point_global_m;
  r.point_local_m = sent.goal_m;
  r.sent_ns = sent_ns;
  const auto at = std::lower_bound(records_.begin(), records_.end(), r.seq,
                                   [](const CommandRecord& a, uint32_t seq) { return a.seq < seq; });
  records_.insert(at, r);
}

CommandRecord* CommandBook::find(uint32_t seq) {
  const auto at = std::lower_bound(records_.begin(), records_.end(), seq,
                                   [](const CommandRecord& a, uint32_t s) { return a.seq < s; });
  return at != records_.end() && at->seq == seq ? &*at : nullptr;
}

bool CommandBook::on_report(RobotId robot, const CommandReport& report) {
  if (report.seq == 0) return false;
  bool changed = false;
  for (CommandRecord& r : records_) {
    if (r.robot != robot) continue;
    if (r.seq == report.seq && (r.state != report.state || r.note != report.note)) {
      r.state = report.state;
      r.note = report.note;
      changed = true;
    } else if (r.seq < report.seq && (r.state == CommandState::kSent || r.state == CommandState::kReceived ||
                                      r.state == CommandState::kActive)) {
      r.state = CommandState::kOvertaken;
      r.note = "overtaken by command " + std::to_string(report.seq);
      changed = true;
    }
  }
  return changed;
}

std::optional<CommandKind> CommandBook::newest_kind(RobotId robot) const {
  for (auto it = records_.rbegin(); it != records_.rend(); ++it) {
    if (it->robot == robot) return it->kind;
  }
  return std::nullopt;
}

bool CommandBook::under_operator(RobotId robot) const {
  const std::optional<CommandKind> kind = newest_kind(robot);
  return kind && *kind != CommandKind::kResume;
}

}  // namespace cairn::base
