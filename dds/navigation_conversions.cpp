#include "dds/navigation_conversions.h"

#include <cmath>

#include "dds/conversions.h"

namespace cairn::dds {
namespace {

constexpr int kMaxRobotId = 1000;

std::nullopt_t fail(std::string* error, const std::string& what) {
  if (error) *error = what;
  return std::nullopt;
}

bool finite(std::initializer_list<double> values) {
  for (double v : values) {
    if (!std::isfinite(v)) return false;
  }
  return true;
}

}  // namespace

cairn_msgs::VelocityCommand to_msg(const StampedCommand& c) {
  cairn_msgs::VelocityCommand m;
  m.robot_id(c.robot.value);
  m.stamp_ns(c.stamp_ns);
  m.linear_mps(c.command.linear_mps);
  m.angular_radps(c.command.angular_radps);
  m.done(c.done);
  return m;
}

std::optional<StampedCommand> from_msg(const cairn_msgs::VelocityCommand& m, std::string* error) {
  if (m.robot_id() < 0 || m.robot_id() > kMaxRobotId) {
    return fail(error, "cmd_vel: robot_id " + std::to_string(m.robot_id()) + " out of range");
  }
  if (!finite({m.linear_mps(), m.angular_radps()})) return fail(error, "cmd_vel: non-finite linear or angular speed");
  if (m.stamp_ns() < 0) return fail(error, "cmd_vel: negative stamp");
  return StampedCommand{RobotId(m.robot_id()), m.stamp_ns(), {m.linear_mps(), m.angular_radps()}, m.done()};
}

cairn_msgs::ExplorationGoal to_msg(const GoalMessage& g) {
  cairn_msgs::ExplorationGoal m;
  m.robot_id(g.robot.value);
  m.goal_id(g.goal_id);
  m.kind(uint8_t(g.kind));
  m.has_goal(g.has_goal);
  m.x_m(g.goal_m.x());
  m.y_m(g.goal_m.y());
  m.path_m(g.path_m);
  m.frontier_m(g.frontier_m);
  return m;
}

std::optional<GoalMessage> from_msg(const cairn_msgs::ExplorationGoal& m, std::string* error) {
  if (m.robot_id() < 0 || m.robot_id() > kMaxRobotId) {
    return fail(error, "goal: robot_id " + std::to_string(m.robot_id()) + " out of range");
  }
  const auto kind = goal_kind_from(m.kind());
  if (!kind) return fail(error, "goal: unknown kind " + std::to_string(int(m.kind())));
  if (!finite({m.x_m(), m.y_m(), m.path_m(), m.frontier_m()})) return fail(error, "goal: non-finite position");
  if (std::abs(m.x_m()) > 1e5 || std::abs(m.y_m()) > 1e5) return fail(error, "goal: position beyond 100 km");
  GoalMessage g;
  g.robot = RobotId(m.robot_id());
  g.goal_id = m.goal_id();
  g.kind = *kind;
  g.has_goal = m.has_goal();
  g.goal_m = {m.x_m(), m.y_m()};
  g.path_m = m.path_m();
  g.frontier_m = m.frontier_m();
  return g;
}

cairn_msgs::OperatorCommand to_msg(const OperatorCommand& c) {
  cairn_msgs::OperatorCommand m;
  m.robot_id(c.robot.value);
  m.seq(c.seq);
  m.kind(uint8_t(c.kind));
  m.x_m(c.goal_m.x());
  m.y_m(c.goal_m.y());
  return m;
}

std::optional<OperatorCommand> from_msg(const cairn_msgs::OperatorCommand& m, std::string* error) {
  if (m.robot_id() < 0 || m.robot_id() > kMaxRobotId) {
    return fail(error, "operator command: robot_id " + std::to_string(m.robot_id()) + " out of range");
  }
  if (m.seq() == 0) return fail(error, "operator command: seq 0 (sequence numbers start at 1)");
  const auto kind = command_kind_from(m.kind());
  if (!kind) return fail(error, "operator command: unknown kind " + std::to_string(int(m.kind())));
  if (!finite({m.x_m(), m.y_m()})) return fail(error, "operator command: non-finite point");
  if (std::abs(m.x_m()) > 1e5 || std::abs(m.y_m()) > 1e5) return fail(error, "operator command: point beyond 100 km");
  return OperatorCommand{RobotId(m.robot_id()), m.seq(), *kind, {m.x_m(), m.y_m()}};
}

void set_nav_status(const NavStatus& nav, cairn_msgs::RobotStatus* m) {
  m->pose(to_msg(nav.pose));
  m->activity(uint8_t(nav.activity));
  m->goal_id(nav.goal_id);
  m->goal_kind(uint8_t(nav.goal_kind));
  m->nav_state(uint8_t(nav.nav_state));
  m->goal_x_m(nav.goal_m.x());
  m->goal_y_m(nav.goal_m.y());
  m->distance_m(float(nav.distance_m));
  m->command_seq(nav.command.seq);
  m->command_state(uint8_t(nav.command.state));
  m->command_note(eprosima::fastrtps::fixed_string<160>(nav.command.note.substr(0, 160)));
  m->keep_out_version(nav.keep_out_version);
  std::vector<float> xs, ys;
  for (size_t i = 0; i < nav.path_m.size() && i < kMaxStatusPathPoints; ++i) {
    xs.push_back(float(nav.path_m[i].x()));
    ys.push_back(float(nav.path_m[i].y()));
  }
  m->path_x_m(xs);
  m->path_y_m(ys);
}

std::optional<NavStatus> nav_status_from(const cairn_msgs::RobotStatus& m, std::string* error) {
  const auto activity = robot_activity_from(m.activity());
  const auto kind = goal_kind_from(m.goal_kind());
  const auto state = nav_state_from(m.nav_state());
  if (!activity || !kind || !state) return fail(error, "status: unknown activity, goal kind or navigation state");
  const auto command_state = command_state_from(m.command_state());
  if (!command_state) return fail(error, "status: unknown command state " + std::to_string(int(m.command_state())));
  if (!finite({m.pose().x_m(), m.pose().y_m(), m.pose().yaw_rad(), m.goal_x_m(), m.goal_y_m(), m.distance_m()})) {
    return fail(error, "status: non-finite pose, goal or distance");
  }
  NavStatus n;
  n.pose = SE2(m.pose().x_m(), m.pose().y_m(), m.pose().yaw_rad());
  n.activity = *activity;
  n.goal_id = m.goal_id();
  n.goal_kind = *kind;
  n.nav_state = *state;
  n.goal_m = {m.goal_x_m(), m.goal_y_m()};
  n.distance_m = m.distance_m();
  n.command = {m.command_seq(), *command_state, m.command_note().to_string()};
  n.keep_out_version = m.keep_out_version();
  if (m.path_x_m().size() != m.path_y_m().size() || m.path_x_m().size() > kMaxStatusPathPoints) {
    return fail(error, "status: path of " + std::to_string(m.path_x_m().size()) + " x and " +
                           std::to_string(m.path_y_m().size()) + " y coordinates");
  }
  for (size_t i = 0; i < m.path_x_m().size(); ++i) {
    if (!std::isfinite(m.path_x_m()[i]) || !std::isfinite(m.path_y_m()[i])) {
      return fail(error, "status: path point " + std::to_string(i) + " is not finite");
    }
    n.path_m.emplace_back(m.path_x_m()[i], m.path_y_m()[i]);
  }
  return n;
}

cairn_msgs::KeepOutAreas to_msg(const KeepOutMessage& k) {
  cairn_msgs::KeepOutAreas m;
  m.robot_id(k.robot.value);
  m.version(k.version);
  for (size_t i = 0; i < k.areas.size() && i < kMaxKeepOutAreas; ++i) {
    cairn_msgs::KeepOutZone z;
    z.id(k.areas[i].id);
    for (size_t c = 0; c < 4; ++c) {
      z.x_m()[c] = k.areas[i].corners_m[c].x();
      z.y_m()[c] = k.areas[i].corners_m[c].y();
    }
    m.areas().push_back(z);
  }
  return m;
}

std::optional<KeepOutMessage> from_msg(const cairn_msgs::KeepOutAreas& m, std::string* error) {
  if (m.robot_id() < 0 || m.robot_id() > kMaxRobotId) {
    return fail(error, "keep-out areas: robot_id " + std::to_string(m.robot_id()) + " out of range");
  }
  KeepOutMessage k;
  k.robot = RobotId(m.robot_id());
  k.version = m.version();
  for (const cairn_msgs::KeepOutZone& z : m.areas()) {
    KeepOutPolygon p;
    p.id = z.id();
    for (size_t c = 0; c < 4; ++c) p.corners_m[c] = {z.x_m()[c], z.y_m()[c]};
    if (const auto fault = polygon_fault(p)) return fail(error, "keep-out areas: " + *fault);
    k.areas.push_back(p);
  }
  return k;
}

}  // namespace cairn::dds
