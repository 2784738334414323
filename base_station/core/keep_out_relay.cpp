#include "base_station/core/keep_out_relay.h"

#include <cmath>

namespace cairn::base {
namespace {

bool same_areas(const std::vector<KeepOutArea>& a, const std::vector<KeepOutArea>& b) {
  if (a.size() != b.size()) return false;
  for (size_t i = 0; i < a.size(); ++i) {
    if (a[i].id != b[i].id || a[i].min_m != b[i].min_m || a[i].max_m != b[i].max_m) return false;
  }
  return true;
}

KeepOutMessage message_for(RobotId robot, const SE2& T_global_local, const std::vector<KeepOutArea>& areas,
                           uint32_t version) {
  KeepOutMessage m;
  m.robot = robot;
  m.version = version;
  const SE2 T_local_global = T_global_local.inverse();
  for (const KeepOutArea& a : areas) m.areas.push_back(in_frame(a, T_local_global));
  return m;
}

}  // namespace

std::optional<KeepOutMessage> KeepOutRelay::due(const KeepOutRobotState& robot, const std::vector<KeepOutArea>& areas,
                                                double now_s) const {
  if (!robot.linked) return std::nullopt;
  const auto it = sent_.find(robot.robot);
  if (it == sent_.end()) {
    if (areas.empty()) return std::nullopt;  // nothing drawn, nothing to tell
    return message_for(robot.robot, robot.T_global_local, areas, 1);
  }
  const Sent& s = it->second;
  const SE2 moved = s.T_global_local.between(robot.T_global_local);
  const bool changed = !same_areas(s.areas, areas) || moved.translation().norm() > options_.resend_shift_m ||
                       std::abs(moved.yaw()) > options_.resend_turn_rad;
  if (changed) return message_for(robot.robot, robot.T_global_local, areas, s.version + 1);
  const bool lost = robot.held_version != s.version && now_s - s.at_s > options_.unheld_resend_s;
  if (lost) return message_for(robot.robot, s.T_global_local, s.areas, s.version);  // the same again
  return std::nullopt;
}

void KeepOutRelay::mark_sent(const KeepOutRobotState& robot, const std::vector<KeepOutArea>& areas,
                             const KeepOutMessage& message, double now_s) {
  Sent& s = sent_[robot.robot];
  if (message.version != s.version) {  // a new version; a resend keeps the frame and areas it carried
    s.T_global_local = robot.T_global_local;
    s.areas = areas;
  }
  s.version = message.version;
  s.at_s = now_s;
}

uint32_t KeepOutRelay::sent_version(RobotId robot) const {
  const auto it = sent_.find(robot);
  return it == sent_.end() ? 0 : it->second.version;
}

}  // namespace cairn::base
