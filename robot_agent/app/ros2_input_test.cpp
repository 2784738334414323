// The agent's ROS 2 input on a private domain: scan and odometry reach the pipeline; colour and
// aligned depth with the same stamp become one RGB-D frame with the camera mount; a colour image
// whose partner never came is dropped; an image in an encoding Cairn does not take is refused with
// the topic named.
#include "robot_agent/app/ros2_input.h"

#include <gtest/gtest.h>

#include <chrono>
#include <thread>

#include "dds/domain_lease.h"
#include "robot_agent/core/agent_pipeline.h"

namespace cairn::agent {
namespace {

using namespace std::chrono_literals;

dds::ros2::Image image(StampNs stamp_ns, const std::string& encoding, uint32_t bytes_per_pixel) {
  dds::ros2::Image im;
  im.header().stamp(dds::to_ros_time(stamp_ns));
  im.width(4);
  im.height(3);
  im.encoding(encoding);
  im.step(4 * bytes_per_pixel);
  im.data(std::vector<uint8_t>(12 * bytes_per_pixel, 7));
  return im;
}

TEST(Ros2Input, ScansOdometryAndPairedRgbdFramesReachThePipelineAndBadImagesAreNamed) {
  static const auto lease = dds::DomainLease::claim({}, nullptr);
  dds::ParticipantOptions po;
  po.domain_id = lease ? lease->domain_id() : 0;
  std::string error;
  auto participant = dds::Participant::create(po, &error);
  ASSERT_TRUE(participant) << error;
  Ros2InputOptions options;
  options.ros_namespace = "robot3";
  options.T_base_camera = forward_camera_mount(0.5, 10.0);
  Ros2SensorInput input(*participant, options);
  ASSERT_TRUE(input.ok());
  using dds::Ros2Qos;
  auto topic = [&](const std::string& name) { return dds::ros2_dds_topic("robot3", name); };
  dds::Ros2Writer<sensor_msgs::msg::dds_::LaserScan_PubSubType> scan(*participant, topic("scan"), Ros2Qos::kSensorData);
  dds::Ros2Writer<nav_msgs::msg::dds_::Odometry_PubSubType> odom(*participant, topic("odom"), Ros2Qos::kSensorData);
  dds::Ros2Writer<sensor_msgs::msg::dds_::Image_PubSubType> color(*participant, topic(options.color_topic),
                                                                  Ros2Qos::kSensorData);
  dds::Ros2Writer<sensor_msgs::msg::dds_::Image_PubSubType> depth(*participant, topic(options.depth_topic),
                                                                  Ros2Qos::kSensorData);
  dds::Ros2Writer<sensor_msgs::msg::dds_::CameraInfo_PubSubType> info(*participant, topic(options.camera_info_topic),
                                                                      Ros2Qos::kSensorData);
  const auto end = std::chrono::steady_clock::now() + 10s;
  while ((scan.matched_readers() == 0 || odom.matched_readers() == 0 || color.matched_readers() == 0 ||
          depth.matched_readers() == 0 || info.matched_readers() == 0) &&
         std::chrono::steady_clock::now() < end) {
    std::this_thread::sleep_for(10ms);
  }
  dds::ros2::CameraInfo camera;
  camera.width(4);
  camera.height(3);
  camera.k({300, 0, 2, 0, 300, 1.5, 0, 0, 1});
  LaserScan s;
  s.stamp_ns = 2'000'000'000;
  s.angle_min_rad = -1.f;
  s.angle_increment_rad = 0.1f;
  s.ranges_m.assign(21, 3.f);
  ASSERT_TRUE(info.write(camera));
  ASSERT_TRUE(odom.write(dds::to_ros(OdometryReading{2'000'000'000, SE2(0.1, 0, 0), 0, 0}, "odom", "base_link")));
  ASSERT_TRUE(scan.write(dds::to_ros(s, "laser")));
  ASSERT_TRUE(color.write(image(1'000'000'000, "rgb8", 3)));   // its depth image was lost
  ASSERT_TRUE(color.write(image(2'000'000'000, "bgr8", 3)));   // a pair ...
  ASSERT_TRUE(depth.write(image(2'000'000'000, "16UC1", 2)));  // ... by stamp
  ASSERT_TRUE(color.write(image(3'000'000'000, "yuv422", 2)));
  ASSERT_TRUE(depth.write(image(3'000'000'000, "16UC1", 2)));

  AgentPipeline pipeline(RobotId(3));
  std::string problem;
  int fed = 0;
  while (fed < 3 && std::chrono::steady_clock::now() < end) {
    fed += input.feed(&pipeline, &problem);
    std::this_thread::sleep_for(10ms);
  }
  std::this_thread::sleep_for(100ms);
  fed += input.feed(&pipeline, &problem);
  EXPECT_EQ(fed, 3);  // odometry, scan, one RGB-D frame
  EXPECT_EQ(pipeline.stats().rgbd_received, 1);
  EXPECT_EQ(input.refused(), 1);
  EXPECT_EQ(problem, "rt/robot3/camera/color/image_raw: Image: colour encoding \"yuv422\" not taken (rgb8, bgr8)");
  EXPECT_FALSE(input.ended());  // idle_end_s 0: a live robot's input never ends by itself
}

}  // namespace
}  // namespace cairn::agent
