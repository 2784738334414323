#include "tools/mrlog/mrlog_eval.h"

namespace cairn::mrlog {
namespace {

/// summary.json's robots[].given_start, when the base was given one for that robot.
std::optional<SE2> given_start(const nlohmann::json& robot) {
  if (!robot.is_object() || !robot.contains("given_start")) return std::nullopt;
  const nlohmann::json& s = robot["given_start"];
  if (!s.is_object() || !s.contains("x_m") || !s.contains("y_m") || !s.contains("yaw_rad")) return std::nullopt;
  if (!s["x_m"].is_number() || !s["y_m"].is_number() || !s["yaw_rad"].is_number()) return std::nullopt;
  return SE2(s["x_m"].get<double>(), s["y_m"].get<double>(), s["yaw_rad"].get<double>());
}

/// summary.json's robots[].id, when present and an integer.
std::optional<RobotId> robot_id(const nlohmann::json& robot) {
  if (!robot.is_object() || !robot.contains("id") || !robot["id"].is_number_integer()) return std::nullopt;
  return RobotId(robot["id"].get<int>());
}

}  // namespace

std::optional<GlobalFrame> global_frame_of(const MultiRobotLog& log, const nlohmann::json& summary) {
  if (log.robots.empty()) return std::nullopt;
  RobotId anchor = log.robots.begin()->first;
  const bool has_robots = summary.is_object() && summary.contains("robots") && summary["robots"].is_array();
  if (has_robots) {
    // A given start fixes the global frame for every robot: it is the frame the start was given in.
    for (const auto& r : summary["robots"]) {
      const auto start = given_start(r);
      const auto id = robot_id(r);
      if (!start || !id) continue;
      const RobotLogData* data = log.robot(*id);
      if (!data || data->truth.empty()) continue;
      return GlobalFrame{*start * data->truth.front().pose.inverse(),
                         "the start given for robot " + std::to_string(data->robot.value)};
    }
    for (const auto& r : summary["robots"]) {
      if (const auto id = robot_id(r); id && r.value("anchor", false)) anchor = *id;
    }
  }
  const RobotLogData* a = log.robot(anchor);
  if (!a || a->truth.empty()) return std::nullopt;
  return GlobalFrame{a->truth.front().pose.inverse(), "robot " + std::to_string(anchor.value) + "'s start"};
}

}  // namespace cairn::mrlog
