#include "robot_agent/app/ros2_input.h"

#include <cmath>

#include "robot_agent/core/agent_pipeline.h"

namespace cairn::agent {

Eigen::Isometry3d forward_camera_mount(double height_m, double pitch_deg) {
  // Optical axes in the base frame: z_opt = forward (x), x_opt = right (-y), y_opt = down (-z).
  Eigen::Matrix3d R_base_optical;
  R_base_optical << 0, 0, 1, -1, 0, 0, 0, -1, 0;
  const Eigen::AngleAxisd pitch(pitch_deg * M_PI / 180.0, Eigen::Vector3d::UnitY());  // +pitch looks down
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = pitch.toRotationMatrix() * R_base_optical;
  T.translation() = Eigen::Vector3d(0, 0, height_m);
  return T;
}

namespace {
dds::Ros2Qos sensor_qos(const Ros2InputOptions& o) {
  return o.reliable ? dds::Ros2Qos::kReliableSensorData : dds::Ros2Qos::kSensorData;
}
}  // namespace

Ros2SensorInput::Ros2SensorInput(dds::Participant& p, const Ros2InputOptions& o)
    : options_(o),
      scan_(p, dds::ros2_dds_topic(o.ros_namespace, o.scan_topic), sensor_qos(o), o.history_depth),
      odom_(p, dds::ros2_dds_topic(o.ros_namespace, o.odom_topic), sensor_qos(o), o.history_depth),
      color_(p, dds::ros2_dds_topic(o.ros_namespace, o.color_topic), dds::Ros2Qos::kSensorData, 10),
      depth_(p, dds::ros2_dds_topic(o.ros_namespace, o.depth_topic), dds::Ros2Qos::kSensorData, 10),
      info_(p, dds::ros2_dds_topic(o.ros_namespace, o.camera_info_topic), dds::Ros2Qos::kSensorData, 1),
      cmd_vel_(p, dds::ros2_dds_topic(o.ros_namespace, o.cmd_vel_topic), dds::Ros2Qos::kDefault) {}

bool Ros2SensorInput::ok() const {
  return scan_.ok() && odom_.ok() && color_.ok() && depth_.ok() && info_.ok() && cmd_vel_.ok();
}

int Ros2SensorInput::feed(AgentPipeline* pipeline, std::string* problem) {
  int fed = 0;
  std::string error;
  auto refuse = [&](const std::string& topic) {
    ++refused_;
    *problem = dds::ros2_dds_topic(options_.ros_namespace, topic) + ": " + error;
  };
  for (const auto& m : odom_.take_all()) {
    if (auto o = dds::from_ros(m, &error)) {
      pipeline->add_odometry(*o);
      ++fed;
    } else {
      refuse(options_.odom_topic);
    }
  }
  for (const auto& m : scan_.take_all()) {
    if (auto s = dds::from_ros(m, &error)) {
      pipeline->add_scan(*s);
      last_scan_ = Clock::now();
      ++fed;
    } else {
      refuse(options_.scan_topic);
    }
  }
  for (auto& m : info_.take_all()) camera_info_ = std::move(m);
  for (auto& m : color_.take_all()) colors_[dds::from_ros(m.header().stamp())] = std::move(m);
  for (auto& m : depth_.take_all()) depths_[dds::from_ros(m.header().stamp())] = std::move(m);
  // Aligned depth carries its colour image's stamp: a pair is one frame. Unpaired images older
  // than a newer pair are dropped (their partner was lost on the way).
  while (camera_info_ && !colors_.empty() && !depths_.empty()) {
    const StampNs t = std::max(colors_.begin()->first, depths_.begin()->first);
    while (!colors_.empty() && colors_.begin()->first < t) colors_.erase(colors_.begin());
    while (!depths_.empty() && depths_.begin()->first < t) depths_.erase(depths_.begin());
    if (colors_.empty() || depths_.empty()) break;
    auto frame = dds::from_ros(colors_.begin()->second, depths_.begin()->second, *camera_info_, &error);
    colors_.erase(colors_.begin());
    depths_.erase(depths_.begin());
    if (!frame) {
      refuse(options_.color_topic);
      continue;
    }
    frame->T_base_camera = options_.T_base_camera;
    pipeline->add_rgbd(*frame);
    ++fed;
  }
  return fed;
}

bool Ros2SensorInput::ended() const {
  return options_.idle_end_s > 0 && last_scan_ &&
         Clock::now() - *last_scan_ > std::chrono::duration<double>(options_.idle_end_s);
}

void Ros2SensorInput::send_cmd_vel(double linear_mps, double angular_radps) {
  cmd_vel_.write(dds::to_ros_twist(linear_mps, angular_radps));
}

}  // namespace cairn::agent
