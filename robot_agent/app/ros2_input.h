#pragma once
// A ROS 2 robot's own drivers as the agent's sensor input (cairn_agent --ros2): laser, wheel
// odometry and an RGB-D camera on ROS 2 topics (sensor_msgs/LaserScan, nav_msgs/Odometry,
// sensor_msgs/Image colour + aligned depth + CameraInfo), converted and validated by
// dds/ros2_conversions.h and fed to the same AgentPipeline as Cairn's own sensor topics. The
// agent's velocity commands go back out as geometry_msgs/Twist on cmd_vel.
#include <Eigen/Geometry>
#include <chrono>
#include <map>
#include <memory>
#include <optional>
#include <string>

#include "dds/ros2_conversions.h"
#include "dds/ros2_endpoints.h"
#include "ros2_msgsPubSubTypes.h"

namespace cairn::agent {

class AgentPipeline;

struct Ros2InputOptions {
  std::string ros_namespace;  ///< e.g. "robot1": topics rt/robot1/scan, ...
  std::string scan_topic = "scan";
  std::string odom_topic = "odom";
  std::string color_topic = "camera/color/image_raw";
  std::string depth_topic = "camera/aligned_depth_to_color/image_raw";
  std::string camera_info_topic = "camera/color/camera_info";
  std::string cmd_vel_topic = "cmd_vel";
  /// Samples a reader keeps until the agent's poll takes them (sensor-data QoS keeps 5; a bag
  /// replayed at speed needs more so none is dropped while a scan is being matched).
  int history_depth = 200;
  /// Reliable readers for scan and odometry: nothing lost, but only reliable publishers match (a bag
  /// played by cairn_replay); off: ROS 2's sensor-data QoS (best effort), which every driver matches.
  bool reliable = false;
  /// The camera's optical frame in the robot's base frame (no TF listener here).
  Eigen::Isometry3d T_base_camera = Eigen::Isometry3d::Identity();
  /// Input ends after this long with no scan once scans came (a bag played to its end); 0 = never.
  double idle_end_s = 0.0;
};

/// The camera's optical frame (z forward, x right, y down) at `height_m` above the base origin,
/// looking forward, pitched down by `pitch_deg`.
Eigen::Isometry3d forward_camera_mount(double height_m, double pitch_deg);

class Ros2SensorInput {
 public:
  Ros2SensorInput(dds::Participant& participant, const Ros2InputOptions& options);
  bool ok() const;
  /// Feeds everything that arrived to `pipeline` (odometry first, then scans, then RGB-D frames).
  /// Returns how many readings were fed; refused messages are counted and `problem` holds the last.
  int feed(AgentPipeline* pipeline, std::string* problem);
  /// True once scans came and none for idle_end_s.
  bool ended() const;
  int refused() const { return refused_; }
  void send_cmd_vel(double linear_mps, double angular_radps);

 private:
  using Clock = std::chrono::steady_clock;
  Ros2InputOptions options_;
  dds::Ros2Reader<sensor_msgs::msg::dds_::LaserScan_PubSubType> scan_;
  dds::Ros2Reader<nav_msgs::msg::dds_::Odometry_PubSubType> odom_;
  dds::Ros2Reader<sensor_msgs::msg::dds_::Image_PubSubType> color_, depth_;
  dds::Ros2Reader<sensor_msgs::msg::dds_::CameraInfo_PubSubType> info_;
  dds::Ros2Writer<geometry_msgs::msg::dds_::Twist_PubSubType> cmd_vel_;
  std::optional<dds::ros2::CameraInfo> camera_info_;
  std::map<StampNs, dds::ros2::Image> colors_, depths_;  ///< awaiting their partner (same stamp)
  std::optional<Clock::time_point> last_scan_;
  int refused_ = 0;
};

}  // namespace cairn::agent
