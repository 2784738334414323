#pragma once
// An object of interest in the global frame, possibly merged from reports of several robots.
#include <Eigen/Core>
#include <cstdint>
#include <string>
#include <vector>

#include "common/ids.h"
#include "common/point_cloud.h"
#include "common/time.h"

namespace cairn::base {

struct GlobalObject {
  ObjectId id;                          ///< merged id: the smallest ObjectId among its reports
  std::string class_name;
  float confidence = 0.f;               ///< max over reports
  Eigen::Vector3d position_m = Eigen::Vector3d::Zero();  ///< global frame, observation-weighted
  Eigen::Matrix3d covariance = Eigen::Matrix3d::Identity() * 0.01;  ///< of position_m, global
  Eigen::Vector3f size_m = Eigen::Vector3f::Zero();      ///< max extent over reports
  int observations = 0;                 ///< sum over reports
  StampNs last_stamp_ns = 0;
  std::vector<ObjectId> reports;        ///< sorted
  std::vector<RobotId> robots;          ///< sorted, unique
  ColoredCloud cloud_global;            ///< union of the reports' clouds, voxel-downsampled
  std::vector<uint8_t> thumbnail_jpeg;  ///< of the most confident report (may be empty)
};

/// "<robot>-<seq>", safe in URLs and file names (e.g. "1-3").
std::string object_key(ObjectId id);

/// Averages points (position and colour) per cubic voxel; deterministic output order.
ColoredCloud voxel_downsample(const ColoredCloud& cloud, double voxel_m);

}  // namespace cairn::base
