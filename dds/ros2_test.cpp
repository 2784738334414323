// ROS 2 messages: conversions to and from Cairn's readings (and refusals naming the field), the
// DDS names ROS 2 uses, and a LaserScan_ crossing a real domain under ROS 2's sensor-data QoS.
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <cstring>
#include <thread>

#include <fastdds/dds/domain/DomainParticipantFactory.hpp>

#include "dds/domain_lease.h"
#include "dds/ros2_conversions.h"
#include "dds/ros2_endpoints.h"
#include "ros2_msgsPubSubTypes.h"

namespace cairn::dds {
namespace {

ros2::LaserScan scan_msg(int beams) {
  LaserScan s;
  s.stamp_ns = 1'700'000'000'123'456'789;
  s.angle_min_rad = -1.5f;
  s.angle_increment_rad = 0.01f;
  s.ranges_m.assign(beams, 2.5f);
  s.ranges_m[3] = std::numeric_limits<float>::infinity();
  return to_ros(s, "laser");
}

TEST(Ros2, NamesAndTypesAreRos2s) {
  EXPECT_EQ(ros2_dds_topic("robot1", "scan"), "rt/robot1/scan");
  EXPECT_EQ(ros2_dds_topic("/robot1/", "/odom"), "rt/robot1/odom");
  EXPECT_EQ(ros2_dds_topic("", "map"), "rt/map");
  sensor_msgs::msg::dds_::LaserScan_PubSubType scan;
  nav_msgs::msg::dds_::Odometry_PubSubType odom;
  EXPECT_STREQ(scan.getName(), "sensor_msgs::msg::dds_::LaserScan_");
  EXPECT_STREQ(odom.getName(), "nav_msgs::msg::dds_::Odometry_");
}

TEST(Ros2, ALaserScanRoundTripsAndOneWhoseRangesDisagreeWithItsAnglesIsRefused) {
  std::string error;
  const auto s = from_ros(scan_msg(300), &error);
  ASSERT_TRUE(s) << error;
  EXPECT_EQ(s->stamp_ns, 1'700'000'000'123'456'789);
  EXPECT_EQ(s->ranges_m.size(), 300u);
  EXPECT_FLOAT_EQ(s->angle_increment_rad, 0.01f);
  EXPECT_TRUE(std::isinf(s->ranges_m[3]));  // no return: the cores count it

  auto bad = scan_msg(300);
  bad.ranges().resize(250);
  EXPECT_FALSE(from_ros(bad, &error));
  EXPECT_EQ(error.find("LaserScan: 250 ranges"), 0u) << error;
  EXPECT_NE(error.find("give 300"), std::string::npos) << error;
  bad = scan_msg(300);
  bad.intensities().assign(10, 1.f);
  EXPECT_FALSE(from_ros(bad, &error));
  EXPECT_EQ(error, "LaserScan: 10 intensities for 300 ranges");
  bad = scan_msg(300);
  bad.angle_increment(std::nanf(""));
  EXPECT_FALSE(from_ros(bad, &error));
  EXPECT_NE(error.find("bad geometry"), std::string::npos);
}

TEST(Ros2, OdometryCarriesItsPlanarPoseAndRefusesABrokenQuaternion) {
  const OdometryReading o{42, SE2(1.0, -2.0, 2.5), 0.4, -0.2};
  std::string error;
  const auto back = from_ros(to_ros(o, "odom", "base_link"), &error);
  ASSERT_TRUE(back) << error;
  EXPECT_EQ(back->stamp_ns, 42);
  EXPECT_NEAR(back->T_odom_base.x(), 1.0, 1e-12);
  EXPECT_NEAR(back->T_odom_base.yaw(), 2.5, 1e-12);
  EXPECT_DOUBLE_EQ(back->linear_mps, 0.4);
  EXPECT_DOUBLE_EQ(back->angular_radps, -0.2);
  auto m = to_ros(o, "odom", "base_link");
  m.pose().pose().orientation().w(3.0);
  EXPECT_FALSE(from_ros(m, &error));
  EXPECT_NE(error.find("unit quaternion"), std::string::npos);
}

TEST(Ros2, ColourAndDepthInEveryStandardEncodingMakeOneFrameAndOthersAreRefused) {
  ros2::Image color, depth;
  ros2::CameraInfo info;
  for (auto* im : {&color, &depth}) {
    im->width(2);
    im->height(1);
  }
  info.width(2);
  info.height(1);
  info.k({500, 0, 1, 0, 500, 0.5, 0, 0, 1});
  color.encoding("bgr8");
  color.step(6);
  color.data({10, 20, 30, 40, 50, 60});
  depth.encoding("32FC1");
  depth.step(8);
  const float metres[2] = {1.25f, std::nanf("")};
  depth.data().resize(8);
  std::memcpy(depth.data().data(), metres, 8);
  std::string error;
  auto f = from_ros(color, depth, info, &error);
  ASSERT_TRUE(f) << error;
  EXPECT_EQ(f->rgb, (std::vector<uint8_t>{30, 20, 10, 60, 50, 40}));  // bgr -> rgb
  EXPECT_EQ(f->depth, (std::vector<uint16_t>{1250, 0}));              // NaN: no reading
  EXPECT_DOUBLE_EQ(f->intrinsics.fx, 500);
  EXPECT_TRUE(f->valid());

  depth.encoding("16UC1");
  depth.step(4);
  depth.data({0xE2, 0x04, 0x00, 0x00});  // 1250 mm, little-endian
  f = from_ros(color, depth, info, &error);
  ASSERT_TRUE(f) << error;
  EXPECT_EQ(f->depth[0], 1250);

  color.encoding("yuv422");
  EXPECT_FALSE(from_ros(color, depth, info, &error));
  EXPECT_EQ(error, "Image: colour encoding \"yuv422\" not taken (rgb8, bgr8)");
  color.encoding("rgb8");
  depth.width(3);
  EXPECT_FALSE(from_ros(color, depth, info, &error));
  EXPECT_NE(error.find("not one aligned size"), std::string::npos);
}

TEST(Ros2, ALaserScanCrossesTheDomainUnderSensorDataQos) {
  static const auto lease = DomainLease::claim({}, nullptr);
  ParticipantOptions options;
  options.domain_id = lease ? lease->domain_id() : 0;
  std::string error;
  auto participant = Participant::create(options, &error);
  ASSERT_TRUE(participant) << error;
  const std::string topic = ros2_dds_topic("robot1", "scan");
  Ros2Writer<sensor_msgs::msg::dds_::LaserScan_PubSubType> writer(*participant, topic, Ros2Qos::kSensorData);
  Ros2Reader<sensor_msgs::msg::dds_::LaserScan_PubSubType> reader(*participant, topic, Ros2Qos::kSensorData, 50);
  ASSERT_TRUE(writer.ok() && reader.ok());
  const auto end = std::chrono::steady_clock::now() + std::chrono::seconds(10);
  while (writer.matched_readers() == 0 && std::chrono::steady_clock::now() < end) {
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  ASSERT_TRUE(writer.write(scan_msg(360)));
  std::vector<ros2::LaserScan> got;
  while (got.empty() && std::chrono::steady_clock::now() < end) {
    got = reader.take_all();
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  ASSERT_EQ(got.size(), 1u);
  EXPECT_EQ(got[0].ranges().size(), 360u);
  EXPECT_EQ(got[0].header().frame_id(), "laser");
}

// RViz2 as a ROS 2 user starts it: a participant with Fast DDS's defaults (ROS 2's default
// discovery, builtin transports), nothing of Cairn's set-up. It must find a Cairn participant's
// latched map on the same host and get the sample it published before the viewer started.
TEST(Ros2, AParticipantWithRos2DefaultDiscoveryOnThisHostGetsCairnsLatchedMap) {
  using namespace eprosima::fastdds::dds;
  static const auto lease = DomainLease::claim({}, nullptr);
  const int domain = lease ? lease->domain_id() : 0;
  ParticipantOptions options;
  options.domain_id = domain;
  std::string error;
  auto cairn = Participant::create(options, &error);
  ASSERT_TRUE(cairn) << error;
  Ros2Writer<nav_msgs::msg::dds_::OccupancyGrid_PubSubType> map(*cairn, ros2_dds_topic("", "map"), Ros2Qos::kLatched);
  nav_msgs::msg::dds_::OccupancyGrid_ grid;
  grid.info().width(3);
  grid.info().height(2);
  grid.data({0, 100, 255, 0, 0, 0});
  ASSERT_TRUE(map.write(grid));  // before anyone listens: transient local keeps it

  DomainParticipant* viewer =
      DomainParticipantFactory::get_instance()->create_participant(domain, PARTICIPANT_QOS_DEFAULT);
  ASSERT_NE(viewer, nullptr);
  TypeSupport type(new nav_msgs::msg::dds_::OccupancyGrid_PubSubType());
  type.register_type(viewer);
  Topic* topic = viewer->create_topic("rt/map", type.get_type_name(), TOPIC_QOS_DEFAULT);
  Subscriber* subscriber = viewer->create_subscriber(SUBSCRIBER_QOS_DEFAULT);
  DataReaderQos qos = DATAREADER_QOS_DEFAULT;  // what RViz2's map display asks for: reliable, transient local
  qos.reliability().kind = RELIABLE_RELIABILITY_QOS;
  qos.durability().kind = TRANSIENT_LOCAL_DURABILITY_QOS;
  DataReader* reader = subscriber->create_datareader(topic, qos);
  ASSERT_NE(reader, nullptr);
  nav_msgs::msg::dds_::OccupancyGrid_ got;
  SampleInfo info;
  bool received = false;
  const auto end = std::chrono::steady_clock::now() + std::chrono::seconds(15);
  while (!received && std::chrono::steady_clock::now() < end) {
    received =
        reader->take_next_sample(&got, &info) == eprosima::fastrtps::types::ReturnCode_t::RETCODE_OK && info.valid_data;
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  viewer->delete_contained_entities();
  DomainParticipantFactory::get_instance()->delete_participant(viewer);
  ASSERT_TRUE(received);
  EXPECT_EQ(got.info().width(), 3u);
  EXPECT_EQ(got.data().size(), 6u);
}

}  // namespace
}  // namespace cairn::dds
