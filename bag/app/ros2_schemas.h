#pragma once
// The ROS 2 message definitions (.msg, Jazzy) of the ROS 2 types Cairn writes into bags, in the
// form MCAP's ros2msg schema encoding takes: the type's definition, then each type it uses after
// a line of 80 '=' and "MSG: package/Type" (https://mcap.dev/spec/registry). Readers such as
// Foxglove decode the messages from this text alone.
#include <optional>
#include <string>

namespace cairn::bag {

/// The ros2msg schema text of `ros_type` ("sensor_msgs/msg/LaserScan"), or nullopt for a type
/// Cairn does not write.
std::optional<std::string> ros2msg_schema(const std::string& ros_type);

}  // namespace cairn::bag
