#pragma once
// ROS 2 messages (idl/ros2_msgs.idl) <-> Cairn's plain C++ readings. from_ros() validates like
// dds::from_msg(): a message that cannot be trusted (a LaserScan whose range count disagrees with
// its angles, a NaN pose, an image encoding Cairn does not take) gives nullopt and an error naming
// the field, and never reaches the cores.
#include <optional>
#include <string>

#include "common/laser_scan.h"
#include "common/sensors.h"
#include "ros2_msgs.h"

namespace cairn::dds {

namespace ros2 {
using Time = builtin_interfaces::msg::dds_::Time_;
using LaserScan = sensor_msgs::msg::dds_::LaserScan_;
using Odometry = nav_msgs::msg::dds_::Odometry_;
using Image = sensor_msgs::msg::dds_::Image_;
using CameraInfo = sensor_msgs::msg::dds_::CameraInfo_;
using Twist = geometry_msgs::msg::dds_::Twist_;
using Quaternion = geometry_msgs::msg::dds_::Quaternion_;
}  // namespace ros2

StampNs from_ros(const ros2::Time& t);
ros2::Time to_ros_time(StampNs stamp_ns);
/// Yaw of a quaternion about z; nullopt when it is not finite or far from unit length.
std::optional<double> yaw_of(const ros2::Quaternion& q);
ros2::Quaternion quaternion_of_yaw(double yaw_rad);

std::optional<LaserScan> from_ros(const ros2::LaserScan& msg, std::string* error);
ros2::LaserScan to_ros(const LaserScan& scan, const std::string& frame_id);

std::optional<OdometryReading> from_ros(const ros2::Odometry& msg, std::string* error);
ros2::Odometry to_ros(const OdometryReading& odom, const std::string& frame_id, const std::string& child_frame_id);

/// A colour image (rgb8, bgr8) and its aligned depth image (16UC1 millimetres, 32FC1 metres) of the
/// same size, with the camera's intrinsics: one RgbdFrame (depth in millimetres), stamped by the colour image.
std::optional<RgbdFrame> from_ros(const ros2::Image& color, const ros2::Image& depth, const ros2::CameraInfo& info,
                                  std::string* error);

ros2::Twist to_ros_twist(double linear_mps, double angular_radps);

}  // namespace cairn::dds
