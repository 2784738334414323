#pragma once
// The mission as ROS 2 topics (cairn_base --ros2), so RViz2 and Foxglove show it with no bridge:
//   rt/map                nav_msgs/OccupancyGrid, transient local (as map_server offers it)
//   rt/tf                 tf2_msgs/TFMessage: map -> robotN/odom (the base's corrections) and
//                         robotN/odom -> robotN/base_link (each robot's newest reported pose)
//   rt/robotN/path        nav_msgs/Path: a linked robot's merged keyframe poses
//   rt/cairn/objects      visualization_msgs/MarkerArray: each object's box in its class colour,
//                         its label, and its 2-sigma position-uncertainty ellipsoid
//   rt/cairn/object_clouds sensor_msgs/PointCloud2: the objects' coloured points (x y z rgb)
// Only placed robots and objects: the ROS frames hang off "map". The message builders are free
// functions (tested without DDS); Ros2Output holds the writers and publishes when the map changed.
#include <map>
#include <memory>
#include <optional>
#include <string>

#include "base_station/core/merged_map.h"
#include "dds/ros2_endpoints.h"
#include "ros2_msgsPubSubTypes.h"

namespace cairn::base {

namespace ros2 {
using OccupancyGrid = nav_msgs::msg::dds_::OccupancyGrid_;
using TFMessage = tf2_msgs::msg::dds_::TFMessage_;
using Path = nav_msgs::msg::dds_::Path_;
using MarkerArray = visualization_msgs::msg::dds_::MarkerArray_;
using PointCloud2 = sensor_msgs::msg::dds_::PointCloud2_;
}  // namespace ros2

/// -1 unknown, 0..100 occupied probability in percent; row 0 at the origin (ROS's convention too).
ros2::OccupancyGrid to_occupancy_grid(const OccupancyGrid& grid, StampNs stamp_ns);
/// map -> robotN/odom for every placed robot; robotN/odom -> robotN/base_link where a pose is known.
ros2::TFMessage to_tf(const MergedMap& merged, const std::map<RobotId, SE2>& robot_poses, StampNs stamp_ns);
ros2::Path to_path(const Trajectory& trajectory, StampNs stamp_ns);
/// A DELETEALL, then per placed object: box (ns "objects"), label (ns "labels"), ellipsoid (ns "uncertainty").
ros2::MarkerArray to_markers(const MergedMap& merged, StampNs stamp_ns);
ros2::PointCloud2 to_object_cloud(const MergedMap& merged, StampNs stamp_ns);
std::string robot_frame(RobotId robot, const char* frame);  ///< "robot1/odom"

class Ros2Output {
 public:
  explicit Ros2Output(dds::Participant& participant);
  bool ok() const;
  /// Publishes what changed since the last call (the map, paths, markers and clouds when the
  /// merge's version moved; the frames every call).
  void publish(const MergedMap& merged, const std::map<RobotId, SE2>& robot_poses, StampNs stamp_ns);

 private:
  dds::Participant& participant_;
  dds::Ros2Writer<nav_msgs::msg::dds_::OccupancyGrid_PubSubType> map_;
  dds::Ros2Writer<tf2_msgs::msg::dds_::TFMessage_PubSubType> tf_;
  dds::Ros2Writer<visualization_msgs::msg::dds_::MarkerArray_PubSubType> markers_;
  dds::Ros2Writer<sensor_msgs::msg::dds_::PointCloud2_PubSubType> clouds_;
  std::map<RobotId, std::unique_ptr<dds::Ros2Writer<nav_msgs::msg::dds_::Path_PubSubType>>> paths_;
  std::optional<uint64_t> published_version_;
};

}  // namespace cairn::base
