#pragma once
// Raw sensor readings as the simulator, a log or a driver provides them (plain C++, no DDS).
// Frames: the robot base frame is x forward, y left, z up; the 2D laser sits at the base origin
// (T_base_laser = identity); the camera uses the optical convention (z forward, x right, y down)
// and T_base_camera maps camera points into the base frame.
#include <Eigen/Geometry>
#include <cstdint>
#include <vector>

#include "common/se2.h"
#include "common/time.h"

namespace cairn {

/// Wheel odometry: the robot's pose in its odometry frame (drifts), integrated by the driver.
struct OdometryReading {
  StampNs stamp_ns = 0;
  SE2 T_odom_base;
  double linear_mps = 0.0;
  double angular_radps = 0.0;
};

struct CameraIntrinsics {
  int width = 0, height = 0;
  double fx = 0, fy = 0, cx = 0, cy = 0;
  double depth_scale_m = 0.001;  ///< metres per depth unit (uint16 millimetres by default)
};

/// One registered RGB-D frame: colour and depth share the same pixel grid.
struct RgbdFrame {
  StampNs stamp_ns = 0;
  CameraIntrinsics intrinsics;
  Eigen::Isometry3d T_base_camera = Eigen::Isometry3d::Identity();
  std::vector<uint8_t> rgb;     ///< RGB8, row-major, width*height*3
  std::vector<uint16_t> depth;  ///< depth units (see depth_scale_m), 0 = no reading
  bool valid() const {
    const size_t n = size_t(intrinsics.width) * size_t(intrinsics.height);
    return n > 0 && rgb.size() == 3 * n && depth.size() == n;
  }
};

}  // namespace cairn
