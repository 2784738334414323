// Taps and players on a private domain: what a tap records is the CDR a player turns back into
// the same sample; robots are filtered; bytes that do not decode, unknown topics and a topic
// recorded under another type are refused with their names.
#include "bag/app/topic_bag.h"

#include <gtest/gtest.h>
#include "bag/app/ros2_schemas.h"

#include <chrono>
#include <thread>

#include "dds/cdr.h"
#include "dds/domain_lease.h"
#include "dds/endpoints.h"

namespace cairn::bag {
namespace {

int test_domain() {
  static const std::unique_ptr<dds::DomainLease> lease = dds::DomainLease::claim({}, nullptr);
  return lease ? lease->domain_id() : 0;
}

template <typename Pred>
bool wait_for(Pred done, double timeout_s = 10.0) {
  const auto end = std::chrono::steady_clock::now() + std::chrono::duration<double>(timeout_s);
  while (!done()) {
    if (std::chrono::steady_clock::now() > end) return false;
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  return true;
}

TEST(TopicBag, PerRobotTopicNamesGiveTheirRobot) {
  EXPECT_EQ(robot_of_topic("cairn/robot3/odometry"), 3);
  EXPECT_EQ(robot_of_topic("cairn/robot12/laser_scan"), 12);
  EXPECT_FALSE(robot_of_topic("cairn/keyframe"));
  EXPECT_FALSE(robot_of_topic("cairn/robotX/odometry"));
  EXPECT_NE(cairn_idl_text().find("struct Keyframe"), std::string::npos);
}

TEST(TopicBag, Ros2SchemasCarryEveryTypeTheyUse) {
  const auto scan = ros2msg_schema("sensor_msgs/msg/LaserScan");
  ASSERT_TRUE(scan);
  EXPECT_EQ(scan->find("std_msgs/Header header\nfloat32 angle_min\n"), 0u);
  EXPECT_NE(scan->find(std::string(80, '=') + "\nMSG: builtin_interfaces/Time\nint32 sec\n"), std::string::npos);
  const auto odom = ros2msg_schema("nav_msgs/msg/Odometry");
  ASSERT_TRUE(odom);
  EXPECT_NE(odom->find("MSG: geometry_msgs/Quaternion\nfloat64 x 0\n"), std::string::npos);
  EXPECT_FALSE(ros2msg_schema("sensor_msgs/msg/Imu"));
  EXPECT_FALSE(ros2msg_schema("LaserScan"));
}

TEST(TopicBag, TapsCoverEveryTopicAndEachRobotsSensorTopics) {
  std::string error;
  dds::ParticipantOptions options;
  options.domain_id = test_domain();
  auto participant = dds::Participant::create(options, &error);
  ASSERT_TRUE(participant) << error;
  auto all = make_taps(*participant, 2, [](const std::string&) { return true; });
  std::vector<std::string> names;
  for (const auto& t : all) names.push_back(t->topic());
  EXPECT_NE(std::find(names.begin(), names.end(), "cairn/robot1/laser_scan"), names.end());
  EXPECT_NE(std::find(names.begin(), names.end(), "cairn/keyframe"), names.end());
  EXPECT_EQ(std::find(names.begin(), names.end(), "cairn/robot2/laser_scan"), names.end());
  auto some = make_taps(*participant, 2, [](const std::string& t) { return t.find("status") != std::string::npos; });
  ASSERT_EQ(some.size(), 1u);
  EXPECT_EQ(some[0]->type_name(), "cairn_msgs::RobotStatus");
}

TEST(TopicBag, ARecordedSampleIsPlayedBackAsTheSameSampleAndBadBytesAreRefused) {
  std::string error;
  dds::ParticipantOptions options;
  options.domain_id = test_domain();
  auto participant = dds::Participant::create(options, &error);
  ASSERT_TRUE(participant) << error;
  auto taps = make_taps(*participant, 0, [](const std::string& t) { return t == "cairn/status"; });
  ASSERT_EQ(taps.size(), 1u);
  auto player = make_player(*participant, "cairn/status", "cairn_msgs::RobotStatus", &error);
  ASSERT_TRUE(player) << error;
  ASSERT_TRUE(wait_for([&] { return player->matched_readers() > 0; }));

  cairn_msgs::RobotStatus status;
  status.robot_id(2);
  status.keyframes_sent(17);
  status.pose().x_m(1.5);
  const auto cdr = dds::to_cdr<cairn_msgs::RobotStatusPubSubType>(status);
  auto take_one = [&] {
    std::vector<TappedSample> got;
    wait_for([&] {
      for (auto& s : taps[0]->take()) got.push_back(std::move(s));
      return !got.empty();
    });
    return got;
  };
  EXPECT_EQ(player->play(cdr, {}), PlayResult::kWritten);
  auto got = take_one();
  ASSERT_EQ(got.size(), 1u);
  EXPECT_EQ(got[0].cdr, cdr);  // byte for byte what was played
  EXPECT_GT(got[0].received_ns, 0);

  EXPECT_EQ(player->play(cdr, {0, 1}), PlayResult::kFilteredOut);  // robot 2 not asked for
  EXPECT_EQ(player->play({0, 1, 0, 0, 9}, {}), PlayResult::kUndecodable);
  status.robot_id(3);
  const auto cdr3 = dds::to_cdr<cairn_msgs::RobotStatusPubSubType>(status);
  EXPECT_EQ(player->play(cdr3, {3}), PlayResult::kWritten);
  got = take_one();
  ASSERT_EQ(got.size(), 1u);  // robot 3's, and nothing of the filtered robot 2
  EXPECT_EQ(got[0].cdr, cdr3);

  EXPECT_FALSE(make_player(*participant, "/robot1/imu", "sensor_msgs/msg/Imu", &error));
  EXPECT_EQ(error, "/robot1/imu: ROS 2 type sensor_msgs/msg/Imu is not one Cairn replays");
  EXPECT_TRUE(make_player(*participant, "/robot1/scan", "sensor_msgs/msg/LaserScan", &error)) << error;
  EXPECT_FALSE(make_player(*participant, "cairn/robot0/nonsense", "cairn_msgs::Odometry", &error));
  EXPECT_EQ(error, "cairn/robot0/nonsense is not a Cairn topic");
  EXPECT_FALSE(make_player(*participant, "cairn/robot0/odometry", "sensor_msgs::msg::LaserScan", &error));
  EXPECT_EQ(error,
            "cairn/robot0/odometry carries cairn_msgs::Odometry, but the recording says sensor_msgs::msg::LaserScan");
}

}  // namespace
}  // namespace cairn::bag
