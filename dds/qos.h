#pragma once
// Per-topic QoS, in one place (the table in docs/architecture.md).
#include <fastdds/dds/publisher/qos/DataWriterQos.hpp>
#include <fastdds/dds/subscriber/qos/DataReaderQos.hpp>

#include <string>

#include "common/ids.h"

namespace cairn::dds {

enum class TopicKind {
  kSensor,         ///< odometry, laser, RGB-D: reliable, keep all (a replay must not drop input)
  kClock,          ///< mission clock: reliable, transient local, keep last 1
  kKeyframe,       ///< reliable, transient local, keep all: the writer history is the outbox
  kObject,         ///< reliable, transient local, keep last 1 per object, flow-controlled
  kStatus,         ///< best effort, keep last 1
  kAck,            ///< reliable, keep last 1 per robot
  kCorrection,     ///< reliable, transient local, keep last 1 per robot
  kKeyframePoses,  ///< like kCorrection, agent -> base: only the newest estimate matters
  kGoal,           ///< like kCorrection: each robot's newest exploration goal
};

struct QosOptions {
  bool large_data_flow_controlled = false;  ///< objects through the participant's flow controller
};

eprosima::fastdds::dds::DataWriterQos writer_qos(TopicKind kind, const QosOptions& options = {});
eprosima::fastdds::dds::DataReaderQos reader_qos(TopicKind kind);

/// Topic names. Sensor topics are per robot (a driver runs on its robot), the rest are shared
/// and keyed by robot id.
constexpr const char* kOdometryTopic = "odometry";
constexpr const char* kLaserTopic = "laser_scan";
constexpr const char* kRgbdTopic = "rgbd";
inline std::string robot_topic(const char* name, RobotId robot) {
  return "cairn/robot" + std::to_string(robot.value) + "/" + name;
}
constexpr const char* kClockTopic = "cairn/mission_clock";
constexpr const char* kKeyframeTopic = "cairn/keyframe";
constexpr const char* kObjectTopic = "cairn/object";
constexpr const char* kStatusTopic = "cairn/status";
constexpr const char* kAckTopic = "cairn/ack";
constexpr const char* kCorrectionTopic = "cairn/correction";
constexpr const char* kKeyframePosesTopic = "cairn/keyframe_poses";
constexpr const char* kGoalTopic = "cairn/goal";

}  // namespace cairn::dds
