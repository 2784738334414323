#include "base_station/app/ros2_output.h"

#include <Eigen/Eigenvalues>
#include <cmath>
#include <cstring>

#include "dds/ros2_conversions.h"

namespace cairn::base {
namespace {

using Marker = visualization_msgs::msg::dds_::Marker_;
using Header = std_msgs::msg::dds_::Header_;
using Color = std_msgs::msg::dds_::ColorRGBA_;
using Pose = geometry_msgs::msg::dds_::Pose_;

// visualization_msgs/Marker constants.
constexpr int32_t kCube = 1, kSphere = 2, kText = 9, kAdd = 0, kDeleteAll = 3;
// sensor_msgs/PointField FLOAT32.
constexpr uint8_t kFloat32 = 7;

Header header(const std::string& frame, StampNs stamp_ns) {
  Header h;
  h.stamp(dds::to_ros_time(stamp_ns));
  h.frame_id(frame);
  return h;
}

Color color(float r, float g, float b, float a) {
  Color c;
  c.r(r);
  c.g(g);
  c.b(b);
  c.a(a);
  return c;
}

/// The console's class colours: victims red, hazards amber, exits green, anything else blue.
Color class_color(const std::string& class_name, float alpha) {
  if (class_name == "victim") return color(0.90f, 0.12f, 0.12f, alpha);
  if (class_name == "hazard") return color(0.95f, 0.75f, 0.10f, alpha);
  if (class_name == "exit") return color(0.15f, 0.75f, 0.25f, alpha);
  return color(0.25f, 0.45f, 0.90f, alpha);
}

Pose pose_of(const SE2& T) {
  Pose p;
  p.position().x(T.x());
  p.position().y(T.y());
  p.orientation(dds::quaternion_of_yaw(T.yaw()));
  return p;
}

Marker marker(const GlobalObject& o, const char* ns, int32_t type, StampNs stamp_ns) {
  Marker m;
  m.header(header("map", stamp_ns));
  m.ns(ns);
  m.id(int32_t(o.id.robot.value) * 100000 + o.id.seq);
  m.type(type);
  m.action(kAdd);
  m.pose().position().x(o.position_m.x());
  m.pose().position().y(o.position_m.y());
  m.pose().position().z(o.position_m.z());
  m.pose().orientation().w(1.0);
  return m;
}

}  // namespace

std::string robot_frame(RobotId robot, const char* frame) {
  return "robot" + std::to_string(robot.value) + "/" + frame;
}

ros2::OccupancyGrid to_occupancy_grid(const OccupancyGrid& grid, StampNs stamp_ns) {
  ros2::OccupancyGrid m;
  m.header(header("map", stamp_ns));
  m.info().map_load_time(dds::to_ros_time(stamp_ns));
  m.info().resolution(float(grid.resolution_m()));
  m.info().width(uint32_t(grid.width()));
  m.info().height(uint32_t(grid.height()));
  m.info().origin().position().x(grid.origin_m().x());
  m.info().origin().position().y(grid.origin_m().y());
  m.info().origin().orientation().w(1.0);
  std::vector<uint8_t>& data = m.data();
  data.resize(size_t(grid.width()) * size_t(grid.height()));
  for (int row = 0; row < grid.height(); ++row) {
    for (int col = 0; col < grid.width(); ++col) {
      const int8_t v = grid.known(col, row) ? int8_t(std::lround(100.0 * grid.probability(col, row))) : int8_t(-1);
      data[size_t(row) * size_t(grid.width()) + size_t(col)] = uint8_t(v);  // int8 on the wire
    }
  }
  return m;
}

ros2::TFMessage to_tf(const MergedMap& merged, const std::map<RobotId, SE2>& robot_poses, StampNs stamp_ns) {
  ros2::TFMessage m;
  auto add = [&](const std::string& parent, const std::string& child, const SE2& T) {
    geometry_msgs::msg::dds_::TransformStamped_ t;
    t.header(header(parent, stamp_ns));
    t.child_frame_id(child);
    t.transform().translation().x(T.x());
    t.transform().translation().y(T.y());
    t.transform().rotation(dds::quaternion_of_yaw(T.yaw()));
    m.transforms().push_back(t);
  };
  for (const RobotSummary& r : merged.robots) {
    if (!r.linked) continue;
    add("map", robot_frame(r.id, "odom"), r.T_global_local);
    if (const auto pose = robot_poses.find(r.id); pose != robot_poses.end()) {
      add(robot_frame(r.id, "odom"), robot_frame(r.id, "base_link"), pose->second);
    }
  }
  return m;
}

ros2::Path to_path(const Trajectory& trajectory, StampNs stamp_ns) {
  ros2::Path m;
  m.header(header("map", stamp_ns));
  for (const StampedPose& p : trajectory) {
    geometry_msgs::msg::dds_::PoseStamped_ s;
    s.header(header("map", p.stamp_ns));
    s.pose(pose_of(p.pose));
    m.poses().push_back(s);
  }
  return m;
}

ros2::MarkerArray to_markers(const MergedMap& merged, StampNs stamp_ns) {
  ros2::MarkerArray out;
  Marker clear;
  clear.header(header("map", stamp_ns));
  clear.action(kDeleteAll);  // objects merge and vanish: draw the current set afresh
  out.markers().push_back(clear);
  for (const GlobalObject& o : merged.objects) {
    Marker box = marker(o, "objects", kCube, stamp_ns);
    box.scale().x(std::max(0.05f, o.size_m.x()));
    box.scale().y(std::max(0.05f, o.size_m.y()));
    box.scale().z(std::max(0.05f, o.size_m.z()));
    box.color(class_color(o.class_name, 0.8f));
    out.markers().push_back(box);

    Marker label = marker(o, "labels", kText, stamp_ns);
    label.pose().position().z(o.position_m.z() + 0.5 * o.size_m.z() + 0.3);
    label.scale().z(0.3);  // text height
    label.color(color(1, 1, 1, 1));
    char text[96];
    std::snprintf(text, sizeof text, "%s %d-%d (%.2f)", o.class_name.c_str(), o.id.robot.value, o.id.seq,
                  double(o.confidence));
    label.text(text);
    out.markers().push_back(label);

    // The 2-sigma ellipsoid of the position estimate, along the covariance's principal axes.
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(o.covariance);
    Eigen::Matrix3d axes = eig.eigenvectors();
    if (axes.determinant() < 0) axes.col(2) = -axes.col(2);
    const Eigen::Quaterniond q(axes);
    const Eigen::Vector3d diameter = 4.0 * eig.eigenvalues().cwiseMax(1e-8).cwiseSqrt();
    Marker ellipse = marker(o, "uncertainty", kSphere, stamp_ns);
    ellipse.pose().orientation().x(q.x());
    ellipse.pose().orientation().y(q.y());
    ellipse.pose().orientation().z(q.z());
    ellipse.pose().orientation().w(q.w());
    ellipse.scale().x(diameter.x());
    ellipse.scale().y(diameter.y());
    ellipse.scale().z(diameter.z());
    ellipse.color(class_color(o.class_name, 0.3f));
    out.markers().push_back(ellipse);
  }
  return out;
}

ros2::PointCloud2 to_object_cloud(const MergedMap& merged, StampNs stamp_ns) {
  ros2::PointCloud2 m;
  m.header(header("map", stamp_ns));
  const char* names[] = {"x", "y", "z", "rgb"};
  for (uint32_t i = 0; i < 4; ++i) {
    sensor_msgs::msg::dds_::PointField_ f;
    f.name(names[i]);
    f.offset(4 * i);
    f.datatype(kFloat32);
    f.count(1);
    m.fields().push_back(f);
  }
  m.point_step(16);
  m.is_bigendian(false);
  m.is_dense(true);
  std::vector<uint8_t>& data = m.data();
  for (const GlobalObject& o : merged.objects) {
    for (const ColoredPoint& p : o.cloud_global) {
      // rgb as PCL packs it: 0x00RRGGBB in the bytes of a float32.
      const uint32_t rgb = uint32_t(p.r) << 16 | uint32_t(p.g) << 8 | uint32_t(p.b);
      const float xyz[3] = {p.x, p.y, p.z};
      const size_t at = data.size();
      data.resize(at + 16);
      std::memcpy(data.data() + at, xyz, 12);
      std::memcpy(data.data() + at + 12, &rgb, 4);
    }
  }
  m.height(1);
  m.width(uint32_t(data.size() / 16));
  m.row_step(uint32_t(data.size()));
  return m;
}

Ros2Output::Ros2Output(dds::Participant& participant)
    : participant_(participant),
      map_(participant, dds::ros2_dds_topic("", "map"), dds::Ros2Qos::kLatched),
      tf_(participant, dds::ros2_dds_topic("", "tf"), dds::Ros2Qos::kDefault),
      markers_(participant, dds::ros2_dds_topic("cairn", "objects"), dds::Ros2Qos::kLatched),
      clouds_(participant, dds::ros2_dds_topic("cairn", "object_clouds"), dds::Ros2Qos::kLatched) {}

bool Ros2Output::ok() const { return map_.ok() && tf_.ok() && markers_.ok() && clouds_.ok(); }

void Ros2Output::publish(const MergedMap& merged, const std::map<RobotId, SE2>& robot_poses, StampNs stamp_ns) {
  tf_.write(to_tf(merged, robot_poses, stamp_ns));
  if (published_version_ == merged.version) return;
  published_version_ = merged.version;
  if (merged.grid) map_.write(to_occupancy_grid(*merged.grid, stamp_ns));
  for (const auto& [robot, trajectory] : merged.trajectories) {
    auto& writer = paths_[robot];
    if (!writer) {
      writer = std::make_unique<dds::Ros2Writer<nav_msgs::msg::dds_::Path_PubSubType>>(
          participant_, dds::ros2_dds_topic(robot_frame(robot, ""), "path"), dds::Ros2Qos::kLatched);
    }
    writer->write(to_path(trajectory, stamp_ns));
  }
  markers_.write(to_markers(merged, stamp_ns));
  clouds_.write(to_object_cloud(merged, stamp_ns));
}

}  // namespace cairn::base
