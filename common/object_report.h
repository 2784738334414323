#pragma once
// An object of interest (victim, hazard, exit, ...) as a robot reports it; the base station puts
// it into the global frame through its anchor keyframe (T_global_object = T_global_anchor *
// T_anchor_object, with the anchor's planar pose lifted to 3D).
#include <Eigen/Geometry>
#include <cstdint>
#include <string>
#include <vector>

#include "common/ids.h"
#include "common/point_cloud.h"
#include "common/time.h"

namespace cairn {

struct ObjectReport {
  ObjectId id;
  std::string class_name;   ///< "victim", "hazard", "exit", ...
  float confidence = 0.f;   ///< 0..1
  StampNs stamp_ns = 0;     ///< last observation
  int32_t anchor_seq = -1;  ///< keyframe of the same robot the pose is relative to
  Eigen::Isometry3d T_anchor_object = Eigen::Isometry3d::Identity();
  Eigen::Matrix<double, 6, 6> covariance = Eigen::Matrix<double, 6, 6>::Identity() * 0.01;  ///< x y z roll pitch yaw
  int observations = 0;                                                                     ///< frames that contributed
  Eigen::Vector3f size_m = Eigen::Vector3f::Zero();  ///< extent of the cloud's bounding box
  ColoredCloud cloud;                                ///< in the object frame (centred on the object)
  std::vector<uint8_t> thumbnail_jpeg;               ///< may be empty
};

}  // namespace cairn
