#pragma once
// IDL <-> plain C++ for the navigation messages (common/navigation.h): velocity commands, the
// base's goals, the operator's commands and the navigation part of a robot's status.
// from_msg() validates like dds/conversions.h: a NaN, an unknown enum value or an out-of-range
// robot id gives std::nullopt and an error naming the field.
#include <optional>
#include <string>

#include "cairn_msgs.h"
#include "common/keep_out.h"
#include "common/navigation.h"

namespace cairn::dds {

cairn_msgs::VelocityCommand to_msg(const StampedCommand& command);
std::optional<StampedCommand> from_msg(const cairn_msgs::VelocityCommand& msg, std::string* error);

cairn_msgs::ExplorationGoal to_msg(const GoalMessage& goal);
std::optional<GoalMessage> from_msg(const cairn_msgs::ExplorationGoal& msg, std::string* error);

cairn_msgs::OperatorCommand to_msg(const OperatorCommand& command);
std::optional<OperatorCommand> from_msg(const cairn_msgs::OperatorCommand& msg, std::string* error);

/// The IDL's bound on the areas in one message (sequence<KeepOutZone, 64>); more are not sent.
constexpr size_t kMaxKeepOutAreas = 64;
cairn_msgs::KeepOutAreas to_msg(const KeepOutMessage& keep_out);
std::optional<KeepOutMessage> from_msg(const cairn_msgs::KeepOutAreas& msg, std::string* error);

/// Fills the navigation fields of a status message.
void set_nav_status(const NavStatus& nav, cairn_msgs::RobotStatus* msg);
std::optional<NavStatus> nav_status_from(const cairn_msgs::RobotStatus& msg, std::string* error);

}  // namespace cairn::dds
