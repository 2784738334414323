#include "bag/app/topic_bag.h"

#include <algorithm>
#include <regex>
#include "bag/app/ros2_schemas.h"

#include "cairn_msgs_idl_text.h"  // generated from idl/cairn_msgs.idl (bag/CMakeLists.txt)
#include "dds/cdr.h"
#include "dds/endpoints.h"
#include "dds/ros2_endpoints.h"
#include "dds/topics.h"
#include "ros2_msgsPubSubTypes.h"

namespace cairn::bag {
namespace {

template <typename Msg>
std::optional<int> robot_of_msg(const Msg& msg) {
  if constexpr (std::is_same_v<Msg, cairn_msgs::MissionClock>) {
    return std::nullopt;  // the one message that belongs to no robot
  } else {
    return int(msg.robot_id());
  }
}

template <typename Topic>
std::string type_name_of() {
  typename Topic::PubSub type;
  return type.getName();
}

template <typename Topic>
class Tap : public TopicTap {
 public:
  Tap(dds::Participant& participant, std::string name, [[maybe_unused]] RobotId robot)
      : TopicTap(std::move(name), type_name_of<Topic>(), "omgidl", cairn_idl_text()) {
    if constexpr (Topic::kPerRobot) {
      reader_ = std::make_unique<dds::Reader<Topic>>(participant, robot);
    } else {
      reader_ = std::make_unique<dds::Reader<Topic>>(participant);
    }
  }
  std::vector<TappedSample> take() override {
    std::vector<TappedSample> out;
    for (const auto& s : reader_->take_all_from_writers()) {
      out.push_back({s.received_ns, dds::to_cdr<typename Topic::PubSub>(s.msg)});
    }
    return out;
  }

 private:
  std::unique_ptr<dds::Reader<Topic>> reader_;
};

template <typename Topic>
class Player : public TopicPlayer {
 public:
  Player(dds::Participant& participant, [[maybe_unused]] RobotId robot) {
    if constexpr (Topic::kPerRobot) {
      writer_ = std::make_unique<dds::Writer<Topic>>(participant, robot);
    } else {
      writer_ = std::make_unique<dds::Writer<Topic>>(participant);
    }
  }
  PlayResult play(const std::vector<uint8_t>& cdr, const std::vector<int>& robots) override {
    typename Topic::Msg msg;
    if (!dds::from_cdr<typename Topic::PubSub>(cdr, &msg)) return PlayResult::kUndecodable;
    const auto robot = robot_of_msg(msg);
    if (robot && !robots.empty() && std::find(robots.begin(), robots.end(), *robot) == robots.end()) {
      return PlayResult::kFilteredOut;
    }
    return writer_->write(msg) ? PlayResult::kWritten : PlayResult::kWriteFailed;
  }
  int matched_readers() const override { return writer_->matched_readers(); }
  bool flush(double timeout_s) override { return writer_->wait_for_acknowledgments(timeout_s); }

 private:
  std::unique_ptr<dds::Writer<Topic>> writer_;
};

template <typename... Topics>
void add_taps(dds::TopicList<Topics...>, dds::Participant& participant, int robot_count,
              const std::function<bool(const std::string&)>& wanted, std::vector<std::unique_ptr<TopicTap>>* out) {
  auto add = [&](auto topic_tag) {
    using Topic = decltype(topic_tag);
    if constexpr (Topic::kPerRobot) {
      for (int r = 0; r < robot_count; ++r) {
        const std::string name = dds::topic_name<Topic>(RobotId(r));
        if (wanted(name)) out->push_back(std::make_unique<Tap<Topic>>(participant, name, RobotId(r)));
      }
    } else {
      const std::string name = dds::topic_name<Topic>();
      if (wanted(name)) out->push_back(std::make_unique<Tap<Topic>>(participant, name, RobotId()));
    }
  };
  (add(Topics{}), ...);
}

template <typename... Topics>
std::unique_ptr<TopicPlayer> find_player(dds::TopicList<Topics...>, dds::Participant& participant,
                                         const std::string& topic, const std::string& type_name, std::string* why) {
  std::unique_ptr<TopicPlayer> out;
  const auto robot = robot_of_topic(topic);
  auto try_topic = [&](auto topic_tag) {
    using Topic = decltype(topic_tag);
    if (out) return;
    bool same_name = false;
    if constexpr (Topic::kPerRobot) {
      same_name = robot && dds::topic_name<Topic>(RobotId(*robot)) == topic;
    } else {
      same_name = dds::topic_name<Topic>() == topic;
    }
    if (!same_name) return;
    if (type_name_of<Topic>() != type_name) {
      *why = topic + " carries " + type_name_of<Topic>() + ", but the recording says " + type_name;
      return;
    }
    out = std::make_unique<Player<Topic>>(participant, Topic::kPerRobot ? RobotId(*robot) : RobotId());
  };
  (try_topic(Topics{}), ...);
  if (!out && why->empty()) *why = topic + " is not a Cairn topic";
  return out;
}

// A ROS 2 topic ("/map" of "nav_msgs/msg/OccupancyGrid") recorded under its ROS name. Arrival is
// stamped when the poll takes it (every few milliseconds), not by Fast DDS.
template <typename PubSub>
class Ros2Tap : public TopicTap {
 public:
  Ros2Tap(dds::Participant& participant, const std::string& ros_topic, const std::string& ros_type, dds::Ros2Qos qos)
      : TopicTap(ros_topic, ros_type, "ros2msg", ros2msg_schema(ros_type).value_or("")),
        reader_(participant, dds::ros2_dds_topic("", ros_topic), qos, 100) {}
  std::vector<TappedSample> take() override {
    std::vector<TappedSample> out;
    for (const auto& m : reader_.take_all()) out.push_back({dds::reception_clock_ns(), dds::to_cdr<PubSub>(m)});
    return out;
  }

 private:
  dds::Ros2Reader<PubSub> reader_;
};

// A ROS 2 channel ("/robot1/scan" of "sensor_msgs/msg/LaserScan") played onto its DDS topic
// ("rt/robot1/scan"). ROS 2 messages name no robot: --robots does not filter them.
template <typename PubSub>
class Ros2Player : public TopicPlayer {
 public:
  // A deep history: a reliable subscriber (cairn_agent --ros2-reliable) gets every message back.
  Ros2Player(dds::Participant& participant, const std::string& ros_topic, dds::Ros2Qos qos)
      : writer_(participant, dds::ros2_dds_topic("", ros_topic), qos, 1000) {}
  PlayResult play(const std::vector<uint8_t>& cdr, const std::vector<int>&) override {
    typename PubSub::type msg;
    if (!dds::from_cdr<PubSub>(cdr, &msg)) return PlayResult::kUndecodable;
    return writer_.write(msg) ? PlayResult::kWritten : PlayResult::kWriteFailed;
  }
  int matched_readers() const override { return writer_.matched_readers(); }
  bool flush(double timeout_s) override { return writer_.wait_for_acknowledgments(timeout_s); }

 private:
  dds::Ros2Writer<PubSub> writer_;
};

std::unique_ptr<TopicPlayer> make_ros2_player(dds::Participant& p, const std::string& topic,
                                              const std::string& type_name) {
  using dds::Ros2Qos;
  if (type_name == "sensor_msgs/msg/LaserScan")
    return std::make_unique<Ros2Player<sensor_msgs::msg::dds_::LaserScan_PubSubType>>(p, topic, Ros2Qos::kSensorData);
  if (type_name == "nav_msgs/msg/Odometry")
    return std::make_unique<Ros2Player<nav_msgs::msg::dds_::Odometry_PubSubType>>(p, topic, Ros2Qos::kSensorData);
  if (type_name == "sensor_msgs/msg/Image")
    return std::make_unique<Ros2Player<sensor_msgs::msg::dds_::Image_PubSubType>>(p, topic, Ros2Qos::kSensorData);
  if (type_name == "sensor_msgs/msg/CameraInfo")
    return std::make_unique<Ros2Player<sensor_msgs::msg::dds_::CameraInfo_PubSubType>>(p, topic, Ros2Qos::kSensorData);
  if (type_name == "geometry_msgs/msg/Twist")
    return std::make_unique<Ros2Player<geometry_msgs::msg::dds_::Twist_PubSubType>>(p, topic, Ros2Qos::kDefault);
  if (type_name == "nav_msgs/msg/OccupancyGrid")
    return std::make_unique<Ros2Player<nav_msgs::msg::dds_::OccupancyGrid_PubSubType>>(p, topic, Ros2Qos::kLatched);
  if (type_name == "tf2_msgs/msg/TFMessage")
    return std::make_unique<Ros2Player<tf2_msgs::msg::dds_::TFMessage_PubSubType>>(p, topic, Ros2Qos::kDefault);
  if (type_name == "nav_msgs/msg/Path")
    return std::make_unique<Ros2Player<nav_msgs::msg::dds_::Path_PubSubType>>(p, topic, Ros2Qos::kLatched);
  if (type_name == "visualization_msgs/msg/MarkerArray")
    return std::make_unique<Ros2Player<visualization_msgs::msg::dds_::MarkerArray_PubSubType>>(p, topic,
                                                                                               Ros2Qos::kLatched);
  if (type_name == "sensor_msgs/msg/PointCloud2")
    return std::make_unique<Ros2Player<sensor_msgs::msg::dds_::PointCloud2_PubSubType>>(p, topic, Ros2Qos::kLatched);
  return nullptr;
}

}  // namespace

const std::string& cairn_idl_text() {
  static const std::string text = kCairnMsgsIdl;
  return text;
}

bool topic_wanted(const std::string& topic, const std::vector<std::string>& words) {
  return words.empty() || std::any_of(words.begin(), words.end(),
                                      [&](const std::string& w) { return topic.find(w) != std::string::npos; });
}

std::optional<int> robot_of_topic(const std::string& topic) {
  static const std::regex per_robot(R"(cairn/robot(\d{1,4})/.+)");
  std::smatch m;
  if (!std::regex_match(topic, m, per_robot)) return std::nullopt;
  return std::stoi(m[1].str());
}

std::vector<std::unique_ptr<TopicTap>> make_taps(dds::Participant& participant, int robot_count,
                                                 const std::function<bool(const std::string&)>& wanted) {
  std::vector<std::unique_ptr<TopicTap>> out;
  add_taps(dds::AllTopics{}, participant, robot_count, wanted, &out);
  return out;
}

std::vector<std::unique_ptr<TopicTap>> make_ros2_taps(dds::Participant& p, int robot_count, bool reliable) {
  using dds::Ros2Qos;
  const Ros2Qos sensor = reliable ? Ros2Qos::kReliableSensorData : Ros2Qos::kSensorData;
  std::vector<std::unique_ptr<TopicTap>> out;
  out.push_back(std::make_unique<Ros2Tap<nav_msgs::msg::dds_::OccupancyGrid_PubSubType>>(
      p, "/map", "nav_msgs/msg/OccupancyGrid", Ros2Qos::kLatched));
  out.push_back(std::make_unique<Ros2Tap<tf2_msgs::msg::dds_::TFMessage_PubSubType>>(p, "/tf", "tf2_msgs/msg/TFMessage",
                                                                                     Ros2Qos::kDefault));
  out.push_back(std::make_unique<Ros2Tap<visualization_msgs::msg::dds_::MarkerArray_PubSubType>>(
      p, "/cairn/objects", "visualization_msgs/msg/MarkerArray", Ros2Qos::kLatched));
  out.push_back(std::make_unique<Ros2Tap<sensor_msgs::msg::dds_::PointCloud2_PubSubType>>(
      p, "/cairn/object_clouds", "sensor_msgs/msg/PointCloud2", Ros2Qos::kLatched));
  for (int r = 0; r < robot_count; ++r) {
    const std::string ns = "/robot" + std::to_string(r) + "/";
    out.push_back(std::make_unique<Ros2Tap<nav_msgs::msg::dds_::Path_PubSubType>>(p, ns + "path", "nav_msgs/msg/Path",
                                                                                  Ros2Qos::kLatched));
    out.push_back(std::make_unique<Ros2Tap<sensor_msgs::msg::dds_::LaserScan_PubSubType>>(
        p, ns + "scan", "sensor_msgs/msg/LaserScan", sensor));
    out.push_back(std::make_unique<Ros2Tap<nav_msgs::msg::dds_::Odometry_PubSubType>>(p, ns + "odom",
                                                                                      "nav_msgs/msg/Odometry", sensor));
    out.push_back(std::make_unique<Ros2Tap<geometry_msgs::msg::dds_::Twist_PubSubType>>(
        p, ns + "cmd_vel", "geometry_msgs/msg/Twist", Ros2Qos::kSensorData));
  }
  return out;
}

std::unique_ptr<TopicPlayer> make_player(dds::Participant& participant, const std::string& topic,
                                         const std::string& type_name, std::string* why) {
  why->clear();
  if (type_name.find("/msg/") != std::string::npos) {  // a ROS 2 type: a ROS 2 bag's channel
    auto player = make_ros2_player(participant, topic, type_name);
    if (!player) *why = topic + ": ROS 2 type " + type_name + " is not one Cairn replays";
    return player;
  }
  return find_player(dds::AllTopics{}, participant, topic, type_name, why);
}

}  // namespace cairn::bag
