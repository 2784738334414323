#include "dds/ros2_conversions.h"

#include <cmath>
#include <cstring>

namespace cairn::dds {
namespace {

bool fail(std::string* error, const std::string& what) {
  if (error) *error = what;
  return false;
}

}  // namespace

StampNs from_ros(const ros2::Time& t) { return StampNs(t.sec()) * kNsPerSec + StampNs(t.nanosec()); }

ros2::Time to_ros_time(StampNs stamp_ns) {
  ros2::Time t;
  StampNs sec = stamp_ns / kNsPerSec, ns = stamp_ns % kNsPerSec;
  if (ns < 0) --sec, ns += kNsPerSec;
  t.sec(int32_t(sec));
  t.nanosec(uint32_t(ns));
  return t;
}

std::optional<double> yaw_of(const ros2::Quaternion& q) {
  const double n = std::sqrt(q.x() * q.x() + q.y() * q.y() + q.z() * q.z() + q.w() * q.w());
  if (!std::isfinite(n) || std::abs(n - 1.0) > 0.01) return std::nullopt;
  return std::atan2(2.0 * (q.w() * q.z() + q.x() * q.y()), 1.0 - 2.0 * (q.y() * q.y() + q.z() * q.z()));
}

ros2::Quaternion quaternion_of_yaw(double yaw_rad) {
  ros2::Quaternion q;
  q.z(std::sin(0.5 * yaw_rad));
  q.w(std::cos(0.5 * yaw_rad));
  return q;
}

std::optional<LaserScan> from_ros(const ros2::LaserScan& m, std::string* error) {
  if (!std::isfinite(m.angle_min()) || !std::isfinite(m.angle_max()) || !std::isfinite(m.angle_increment()) ||
      m.angle_increment() == 0.f || !(m.range_max() > m.range_min()) || m.ranges().empty()) {
    fail(error,
         "LaserScan: bad geometry (angles not finite, zero angle_increment, range_max <= range_min, or no "
         "ranges)");
    return std::nullopt;
  }
  // ROS: ranges holds (angle_max - angle_min) / angle_increment + 1 beams; drivers round either way.
  const double beams = double(m.angle_max() - m.angle_min()) / double(m.angle_increment()) + 1.0;
  if (std::abs(beams - double(m.ranges().size())) > 1.5) {
    fail(error, "LaserScan: " + std::to_string(m.ranges().size()) + " ranges, but angle_min " +
                    std::to_string(m.angle_min()) + ", angle_max " + std::to_string(m.angle_max()) +
                    " and angle_increment " + std::to_string(m.angle_increment()) + " give " +
                    std::to_string(int(std::lround(beams))));
    return std::nullopt;
  }
  if (!m.intensities().empty() && m.intensities().size() != m.ranges().size()) {
    fail(error, "LaserScan: " + std::to_string(m.intensities().size()) + " intensities for " +
                    std::to_string(m.ranges().size()) + " ranges");
    return std::nullopt;
  }
  LaserScan s;
  s.stamp_ns = from_ros(m.header().stamp());
  s.angle_min_rad = m.angle_min();
  s.angle_increment_rad = m.angle_increment();
  s.range_min_m = m.range_min();
  s.range_max_m = m.range_max();
  s.ranges_m = m.ranges();
  s.intensities = m.intensities();
  return s;
}

ros2::LaserScan to_ros(const LaserScan& scan, const std::string& frame_id) {
  ros2::LaserScan m;
  m.header().stamp(to_ros_time(scan.stamp_ns));
  m.header().frame_id(frame_id);
  m.angle_min(scan.angle_min_rad);
  m.angle_increment(scan.angle_increment_rad);
  m.angle_max(scan.angle_min_rad + scan.angle_increment_rad * float(scan.ranges_m.size() - 1));
  m.range_min(scan.range_min_m);
  m.range_max(scan.range_max_m);
  m.ranges(scan.ranges_m);
  m.intensities(scan.intensities);
  return m;
}

std::optional<OdometryReading> from_ros(const ros2::Odometry& m, std::string* error) {
  const auto& p = m.pose().pose().position();
  const auto yaw = yaw_of(m.pose().pose().orientation());
  const auto& v = m.twist().twist();
  if (!std::isfinite(p.x()) || !std::isfinite(p.y()) || !yaw) {
    fail(error, "Odometry: pose not finite, or its orientation is not a unit quaternion");
    return std::nullopt;
  }
  if (!std::isfinite(v.linear().x()) || !std::isfinite(v.angular().z())) {
    fail(error, "Odometry: twist not finite");
    return std::nullopt;
  }
  return OdometryReading{from_ros(m.header().stamp()), SE2(p.x(), p.y(), *yaw), v.linear().x(), v.angular().z()};
}

ros2::Odometry to_ros(const OdometryReading& odom, const std::string& frame_id, const std::string& child_frame_id) {
  ros2::Odometry m;
  m.header().stamp(to_ros_time(odom.stamp_ns));
  m.header().frame_id(frame_id);
  m.child_frame_id(child_frame_id);
  m.pose().pose().position().x(odom.T_odom_base.x());
  m.pose().pose().position().y(odom.T_odom_base.y());
  m.pose().pose().orientation(quaternion_of_yaw(odom.T_odom_base.yaw()));
  m.twist().twist() = to_ros_twist(odom.linear_mps, odom.angular_radps);
  return m;
}

ros2::Twist to_ros_twist(double linear_mps, double angular_radps) {
  ros2::Twist t;
  t.linear().x(linear_mps);
  t.angular().z(angular_radps);
  return t;
}

std::optional<RgbdFrame> from_ros(const ros2::Image& color, const ros2::Image& depth, const ros2::CameraInfo& info,
                                  std::string* error) {
  const uint32_t w = color.width(), h = color.height();
  if (w == 0 || h == 0 || depth.width() != w || depth.height() != h || info.width() != w || info.height() != h) {
    fail(error, "Image: colour " + std::to_string(w) + "x" + std::to_string(h) + ", depth " +
                    std::to_string(depth.width()) + "x" + std::to_string(depth.height()) + ", camera_info " +
                    std::to_string(info.width()) + "x" + std::to_string(info.height()) + ": not one aligned size");
    return std::nullopt;
  }
  const size_t n = size_t(w) * h;
  RgbdFrame f;
  f.stamp_ns = from_ros(color.header().stamp());
  f.intrinsics = {int(w), int(h), info.k()[0], info.k()[4], info.k()[2], info.k()[5], 0.001};
  if (!(f.intrinsics.fx > 0) || !(f.intrinsics.fy > 0) || !std::isfinite(f.intrinsics.cx) ||
      !std::isfinite(f.intrinsics.cy)) {
    fail(error, "CameraInfo: k holds no usable focal lengths");
    return std::nullopt;
  }
  const bool rgb = color.encoding() == "rgb8", bgr = color.encoding() == "bgr8";
  if (!rgb && !bgr) {
    fail(error, "Image: colour encoding \"" + color.encoding() + "\" not taken (rgb8, bgr8)");
    return std::nullopt;
  }
  if (color.step() < 3 * w || color.data().size() < size_t(color.step()) * h) {
    fail(error, "Image: colour data holds " + std::to_string(color.data().size()) + " bytes, step " +
                    std::to_string(color.step()) + " x " + std::to_string(h) + " rows needed");
    return std::nullopt;
  }
  f.rgb.resize(3 * n);
  for (uint32_t r = 0; r < h; ++r) {
    const uint8_t* row = color.data().data() + size_t(r) * color.step();
    for (uint32_t c = 0; c < w; ++c) {
      uint8_t* px = f.rgb.data() + 3 * (size_t(r) * w + c);
      px[0] = row[3 * c + (bgr ? 2 : 0)];
      px[1] = row[3 * c + 1];
      px[2] = row[3 * c + (bgr ? 0 : 2)];
    }
  }
  const bool mm = depth.encoding() == "16UC1" || depth.encoding() == "mono16", metres = depth.encoding() == "32FC1";
  const uint32_t bytes = mm ? 2 : 4;
  if (!mm && !metres) {
    fail(error, "Image: depth encoding \"" + depth.encoding() + "\" not taken (16UC1 millimetres, 32FC1 metres)");
    return std::nullopt;
  }
  if (depth.is_bigendian() || depth.step() < bytes * w || depth.data().size() < size_t(depth.step()) * h) {
    fail(error, "Image: depth data holds " + std::to_string(depth.data().size()) + " bytes, step " +
                    std::to_string(depth.step()) + " x " + std::to_string(h) + " rows (little-endian) needed");
    return std::nullopt;
  }
  f.depth.resize(n);
  for (uint32_t r = 0; r < h; ++r) {
    const uint8_t* row = depth.data().data() + size_t(r) * depth.step();
    for (uint32_t c = 0; c < w; ++c) {
      uint16_t& out = f.depth[size_t(r) * w + c];
      if (mm) {
        std::memcpy(&out, row + 2 * c, 2);
      } else {
        float m = 0.f;
        std::memcpy(&m, row + 4 * c, 4);
        out = std::isfinite(m) && m > 0.f && m < 65.f ? uint16_t(std::lround(m * 1000.f)) : 0;  // NaN: no reading
      }
    }
  }
  return f;
}

}  // namespace cairn::dds
