#pragma once
// IDL <-> plain C++ conversions. from_msg() validates every sample: a malformed sample (NaN pose,
// wrong image size, corrupt compressed payload) yields std::nullopt and an error naming the field,
// so a bad sample from the network is dropped with a clear log line and never reaches the cores.
#include <optional>
#include <string>

#include "cairn_msgs.h"
#include "common/keyframe.h"
#include "common/object_report.h"
#include "common/sensors.h"

namespace cairn::dds {

cairn_msgs::Pose2D to_msg(const SE2& pose);

/// A sample on a robot's own topic must carry that robot's id; false (and `error`) otherwise.
bool check_robot(int32_t sample_robot_id, RobotId expected, std::string* error);

cairn_msgs::Odometry to_msg(RobotId robot, const OdometryReading& odom);
std::optional<OdometryReading> from_msg(const cairn_msgs::Odometry& msg, std::string* error);

cairn_msgs::LaserScan to_msg(RobotId robot, const LaserScan& scan);
/// NaN/inf ranges are legal here (the cores filter and count them); geometry must be sane.
std::optional<LaserScan> from_msg(const cairn_msgs::LaserScan& msg, std::string* error);

cairn_msgs::RgbdFrame to_msg(RobotId robot, const RgbdFrame& frame);
std::optional<RgbdFrame> from_msg(const cairn_msgs::RgbdFrame& msg, std::string* error);

cairn_msgs::Keyframe to_msg(const Keyframe& kf);
std::optional<Keyframe> from_msg(const cairn_msgs::Keyframe& msg, std::string* error);

cairn_msgs::KeyframePoses to_msg(const KeyframePoses& poses);
/// Rejects mismatched lengths and non-finite poses (order and seqs are the mapper's to check).
std::optional<KeyframePoses> from_msg(const cairn_msgs::KeyframePoses& msg, std::string* error);

cairn_msgs::ObjectReport to_msg(const ObjectReport& obj);
std::optional<ObjectReport> from_msg(const cairn_msgs::ObjectReport& msg, std::string* error);

}  // namespace cairn::dds
