#pragma once
// The topic table: one trait per DDS topic naming its message type, its generated PubSubType, its
// name and its QoS kind (dds/qos.cpp), so an endpoint is declared from the trait alone:
//   dds::Reader<dds::KeyframeTopic> keyframes(participant);
//   dds::Writer<dds::OdometryTopic> odometry(participant, robot);  // cairn/robot<N>/odometry
// docs/architecture.md "Topics and QoS" lists exactly these topics (checked by dds/topics_test.cpp).
// A new topic gets a trait here and a place in AllTopics (endpoints refuse an unlisted trait).
#include <cstddef>
#include <string>
#include <type_traits>

#include "cairn_msgsPubSubTypes.h"
#include "common/ids.h"
#include "dds/qos.h"

namespace cairn::dds {

// Sensor topics are per robot (a driver runs on its robot): kName holds "<N>", the robot id.
struct OdometryTopic {
  using Msg = cairn_msgs::Odometry;
  using PubSub = cairn_msgs::OdometryPubSubType;
  static constexpr const char* kName = "cairn/robot<N>/odometry";
  static constexpr TopicKind kKind = TopicKind::kSensor;
  static constexpr bool kPerRobot = true;
};
struct LaserScanTopic {
  using Msg = cairn_msgs::LaserScan;
  using PubSub = cairn_msgs::LaserScanPubSubType;
  static constexpr const char* kName = "cairn/robot<N>/laser_scan";
  static constexpr TopicKind kKind = TopicKind::kSensor;
  static constexpr bool kPerRobot = true;
};
struct RgbdTopic {
  using Msg = cairn_msgs::RgbdFrame;
  using PubSub = cairn_msgs::RgbdFramePubSubType;
  static constexpr const char* kName = "cairn/robot<N>/rgbd";
  static constexpr TopicKind kKind = TopicKind::kSensor;
  static constexpr bool kPerRobot = true;
};
struct CmdVelTopic {
  using Msg = cairn_msgs::VelocityCommand;
  using PubSub = cairn_msgs::VelocityCommandPubSubType;
  static constexpr const char* kName = "cairn/robot<N>/cmd_vel";
  static constexpr TopicKind kKind = TopicKind::kCommand;
  static constexpr bool kPerRobot = true;
};

// Shared topics, keyed by robot id where several robots write.
struct ClockTopic {
  using Msg = cairn_msgs::MissionClock;
  using PubSub = cairn_msgs::MissionClockPubSubType;
  static constexpr const char* kName = "cairn/mission_clock";
  static constexpr TopicKind kKind = TopicKind::kClock;
  static constexpr bool kPerRobot = false;
};
struct KeyframeTopic {
  using Msg = cairn_msgs::Keyframe;
  using PubSub = cairn_msgs::KeyframePubSubType;
  static constexpr const char* kName = "cairn/keyframe";
  static constexpr TopicKind kKind = TopicKind::kKeyframe;
  static constexpr bool kPerRobot = false;
};
struct ObjectTopic {
  using Msg = cairn_msgs::ObjectReport;
  using PubSub = cairn_msgs::ObjectReportPubSubType;
  static constexpr const char* kName = "cairn/object";
  static constexpr TopicKind kKind = TopicKind::kObject;
  static constexpr bool kPerRobot = false;
};
struct StatusTopic {
  using Msg = cairn_msgs::RobotStatus;
  using PubSub = cairn_msgs::RobotStatusPubSubType;
  static constexpr const char* kName = "cairn/status";
  static constexpr TopicKind kKind = TopicKind::kStatus;
  static constexpr bool kPerRobot = false;
};
struct AckTopic {
  using Msg = cairn_msgs::Ack;
  using PubSub = cairn_msgs::AckPubSubType;
  static constexpr const char* kName = "cairn/ack";
  static constexpr TopicKind kKind = TopicKind::kAck;
  static constexpr bool kPerRobot = false;
};
struct CorrectionTopic {
  using Msg = cairn_msgs::Correction;
  using PubSub = cairn_msgs::CorrectionPubSubType;
  static constexpr const char* kName = "cairn/correction";
  static constexpr TopicKind kKind = TopicKind::kCorrection;
  static constexpr bool kPerRobot = false;
};
struct GoalTopic {
  using Msg = cairn_msgs::ExplorationGoal;
  using PubSub = cairn_msgs::ExplorationGoalPubSubType;
  static constexpr const char* kName = "cairn/goal";
  static constexpr TopicKind kKind = TopicKind::kGoal;
  static constexpr bool kPerRobot = false;
};
struct OperatorCommandTopic {
  using Msg = cairn_msgs::OperatorCommand;
  using PubSub = cairn_msgs::OperatorCommandPubSubType;
  static constexpr const char* kName = "cairn/operator_command";
  static constexpr TopicKind kKind = TopicKind::kGoal;  // the same QoS: reliable, newest per robot, late-joiner safe
  static constexpr bool kPerRobot = false;
};
struct KeepOutTopic {
  using Msg = cairn_msgs::KeepOutAreas;
  using PubSub = cairn_msgs::KeepOutAreasPubSubType;
  static constexpr const char* kName = "cairn/keep_out";
  static constexpr TopicKind kKind = TopicKind::kGoal;  // reliable, newest per robot, late-joiner safe
  static constexpr bool kPerRobot = false;
};
struct KeyframePosesTopic {
  using Msg = cairn_msgs::KeyframePoses;
  using PubSub = cairn_msgs::KeyframePosesPubSubType;
  static constexpr const char* kName = "cairn/keyframe_poses";
  static constexpr TopicKind kKind = TopicKind::kKeyframePoses;
  static constexpr bool kPerRobot = false;
};

template <typename... Topics>
struct TopicList {};

/// Every topic, in the order of the architecture doc's table.
using AllTopics = TopicList<OdometryTopic, LaserScanTopic, RgbdTopic, CmdVelTopic, ClockTopic, KeyframeTopic,
                            ObjectTopic, StatusTopic, AckTopic, CorrectionTopic, GoalTopic, OperatorCommandTopic,
                            KeepOutTopic, KeyframePosesTopic>;

namespace detail {

template <typename Topic, typename List>
struct Listed;
template <typename Topic, typename... Topics>
struct Listed<Topic, TopicList<Topics...>> : std::disjunction<std::is_same<Topic, Topics>...> {};

constexpr bool equal(const char* a, const char* b) {
  while (*a && *a == *b) ++a, ++b;
  return *a == *b;
}
constexpr bool contains(const char* s, const char* part) {
  for (; *s; ++s) {
    const char *p = part, *q = s;
    while (*p && *p == *q) ++p, ++q;
    if (!*p) return true;
  }
  return false;
}
template <typename Topic>
constexpr bool well_formed() {
  return std::is_same_v<typename Topic::PubSub::type, typename Topic::Msg> &&
         contains(Topic::kName, "<N>") == Topic::kPerRobot;
}
template <typename... Topics>
constexpr bool all_well_formed(TopicList<Topics...>) {
  return (well_formed<Topics>() && ...);
}
template <typename... Topics>
constexpr bool names_distinct(TopicList<Topics...>) {
  const char* names[] = {Topics::kName...};
  for (size_t i = 0; i < sizeof...(Topics); ++i) {
    for (size_t j = i + 1; j < sizeof...(Topics); ++j) {
      if (equal(names[i], names[j])) return false;
    }
  }
  return true;
}

/// kName with "<N>" replaced by the robot id.
inline std::string robot_topic_name(const char* pattern, RobotId robot) {
  std::string name = pattern;
  return name.replace(name.find("<N>"), 3, std::to_string(robot.value));
}

}  // namespace detail

static_assert(detail::all_well_formed(AllTopics{}),
              "a topic's PubSub::type differs from its Msg, or kPerRobot disagrees with a \"<N>\" in kName");
static_assert(detail::names_distinct(AllTopics{}), "two topics share a name");

/// True for a trait in AllTopics.
template <typename Topic>
inline constexpr bool kListedTopic = detail::Listed<Topic, AllTopics>::value;

/// The name of a shared topic.
template <typename Topic>
std::string topic_name() {
  static_assert(kListedTopic<Topic>, "add the topic to AllTopics in dds/topics.h");
  static_assert(!Topic::kPerRobot, "a per-robot topic: pass the robot");
  return Topic::kName;
}
/// The name of a per-robot topic: cairn/robot<N>/... with N the robot's id.
template <typename Topic>
std::string topic_name(RobotId robot) {
  static_assert(kListedTopic<Topic>, "add the topic to AllTopics in dds/topics.h");
  static_assert(Topic::kPerRobot, "a shared topic: no robot");
  return detail::robot_topic_name(Topic::kName, robot);
}

}  // namespace cairn::dds
