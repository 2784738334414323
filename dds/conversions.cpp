#include "dds/conversions.h"

#include <algorithm>
#include <cmath>

#include "common/cloud_codec.h"
#include "common/scan_codec.h"
#include "common/scan_context.h"

namespace cairn::dds {
namespace {

constexpr int kMaxRobotId = 1000;
constexpr int kMaxImagePixels = 4096 * 4096;

bool finite_pose(const cairn_msgs::Pose2D& m) {
  return std::isfinite(m.x_m()) && std::isfinite(m.y_m()) && std::isfinite(m.yaw_rad());
}

SE2 from_to_msg(const cairn_msgs::Pose2D& m) { return SE2(m.x_m(), m.y_m(), m.yaw_rad()); }

template <size_t N>
bool all_finite(const std::array<double, N>& a) {
  return std::all_of(a.begin(), a.end(), [](double v) { return std::isfinite(v); });
}

bool fail(std::string* error, const std::string& what) {
  if (error) *error = what;
  return false;
}

bool valid_robot(int32_t id, std::string* error) {
  if (id < 0 || id > kMaxRobotId) return fail(error, "robot_id " + std::to_string(id) + " out of range");
  return true;
}

std::array<double, 16> iso_to_array(const Eigen::Isometry3d& T) {
  std::array<double, 16> a;
  Eigen::Map<Eigen::Matrix4d>(a.data()) = T.matrix();
  return a;
}

std::optional<Eigen::Isometry3d> array_to_iso(const std::array<double, 16>& a) {
  if (!all_finite(a)) return std::nullopt;
  const Eigen::Matrix4d M = Eigen::Map<const Eigen::Matrix4d>(a.data());
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = M.block<3, 3>(0, 0);
  T.translation() = M.block<3, 1>(0, 3);
  // A rotation must be orthonormal; reject garbage instead of propagating it.
  if ((T.linear() * T.linear().transpose() - Eigen::Matrix3d::Identity()).norm() > 1e-3) return std::nullopt;
  return T;
}

}  // namespace

cairn_msgs::Pose2D to_msg(const SE2& p) {
  cairn_msgs::Pose2D m;
  m.x_m(p.x());
  m.y_m(p.y());
  m.yaw_rad(p.yaw());
  return m;
}

bool check_robot(int32_t sample_robot_id, RobotId expected, std::string* error) {
  if (sample_robot_id == expected.value) return true;
  return fail(error, "sample for unknown robot_id " + std::to_string(sample_robot_id) + " on " + to_string(expected) +
                         "'s topic");
}

cairn_msgs::Odometry to_msg(RobotId robot, const OdometryReading& odom) {
  cairn_msgs::Odometry m;
  m.robot_id(robot.value);
  m.stamp_ns(odom.stamp_ns);
  m.T_odom_base(to_msg(odom.T_odom_base));
  m.linear_mps(odom.linear_mps);
  m.angular_radps(odom.angular_radps);
  return m;
}

std::optional<OdometryReading> from_msg(const cairn_msgs::Odometry& m, std::string* error) {
  if (!valid_robot(m.robot_id(), error)) return std::nullopt;
  if (!finite_pose(m.T_odom_base()) || !std::isfinite(m.linear_mps()) || !std::isfinite(m.angular_radps())) {
    fail(error, "odometry: non-finite T_odom_base or velocity");
    return std::nullopt;
  }
  return OdometryReading{m.stamp_ns(), from_to_msg(m.T_odom_base()), m.linear_mps(), m.angular_radps()};
}

cairn_msgs::LaserScan to_msg(RobotId robot, const LaserScan& scan) {
  cairn_msgs::LaserScan m;
  m.robot_id(robot.value);
  m.stamp_ns(scan.stamp_ns);
  m.angle_min_rad(scan.angle_min_rad);
  m.angle_increment_rad(scan.angle_increment_rad);
  m.range_min_m(scan.range_min_m);
  m.range_max_m(scan.range_max_m);
  m.ranges_m(scan.ranges_m);
  m.intensities(scan.intensities);
  return m;
}

std::optional<LaserScan> from_msg(const cairn_msgs::LaserScan& m, std::string* error) {
  if (!valid_robot(m.robot_id(), error)) return std::nullopt;
  if (!std::isfinite(m.angle_min_rad()) || !std::isfinite(m.angle_increment_rad()) ||
      !(m.range_max_m() > m.range_min_m()) || m.ranges_m().empty()) {
    fail(error, "laser_scan: bad geometry (angles not finite, range_max <= range_min, or no beams)");
    return std::nullopt;
  }
  LaserScan s;
  s.stamp_ns = m.stamp_ns();
  s.angle_min_rad = m.angle_min_rad();
  s.angle_increment_rad = m.angle_increment_rad();
  s.range_min_m = m.range_min_m();
  s.range_max_m = m.range_max_m();
  s.ranges_m = m.ranges_m();
  if (!m.intensities().empty() && m.intensities().size() != m.ranges_m().size()) {
    fail(error, "laser_scan: " + std::to_string(m.intensities().size()) + " intensities for " +
                    std::to_string(m.ranges_m().size()) + " beams");
    return std::nullopt;
  }
  s.intensities = m.intensities();
  return s;
}

cairn_msgs::RgbdFrame to_msg(RobotId robot, const RgbdFrame& f) {
  cairn_msgs::RgbdFrame m;
  m.robot_id(robot.value);
  m.stamp_ns(f.stamp_ns);
  m.width(f.intrinsics.width);
  m.height(f.intrinsics.height);
  m.fx(f.intrinsics.fx);
  m.fy(f.intrinsics.fy);
  m.cx(f.intrinsics.cx);
  m.cy(f.intrinsics.cy);
  m.depth_scale_m(f.intrinsics.depth_scale_m);
  m.T_base_camera(iso_to_array(f.T_base_camera));
  m.rgb(f.rgb);
  m.depth(f.depth);
  return m;
}

std::optional<RgbdFrame> from_msg(const cairn_msgs::RgbdFrame& m, std::string* error) {
  if (!valid_robot(m.robot_id(), error)) return std::nullopt;
  const int64_t n = int64_t(m.width()) * int64_t(m.height());
  if (m.width() <= 0 || m.height() <= 0 || n > kMaxImagePixels) {
    fail(error, "rgbd: bad image size " + std::to_string(m.width()) + "x" + std::to_string(m.height()));
    return std::nullopt;
  }
  if (int64_t(m.rgb().size()) != 3 * n || int64_t(m.depth().size()) != n) {
    fail(error, "rgbd: rgb/depth sizes do not match width*height");
    return std::nullopt;
  }
  if (!(m.fx() > 0) || !(m.fy() > 0) || !std::isfinite(m.cx()) || !std::isfinite(m.cy()) || !(m.depth_scale_m() > 0)) {
    fail(error, "rgbd: bad intrinsics (fx, fy, depth_scale_m must be > 0)");
    return std::nullopt;
  }
  auto T = array_to_iso(m.T_base_camera());
  if (!T) {
    fail(error, "rgbd: T_base_camera is not a finite rigid transform");
    return std::nullopt;
  }
  RgbdFrame f;
  f.stamp_ns = m.stamp_ns();
  f.intrinsics = {m.width(), m.height(), m.fx(), m.fy(), m.cx(), m.cy(), m.depth_scale_m()};
  f.T_base_camera = *T;
  f.rgb = m.rgb();
  f.depth = m.depth();
  return f;
}

cairn_msgs::KeyframePoses to_msg(const KeyframePoses& poses) {
  cairn_msgs::KeyframePoses m;
  m.robot_id(poses.robot.value);
  m.stamp_ns(poses.stamp_ns);
  for (const KeyframePose& p : poses.poses) {
    m.seqs().push_back(p.seq);
    m.T_local_base().push_back(to_msg(p.T_local_base));
  }
  return m;
}

std::optional<KeyframePoses> from_msg(const cairn_msgs::KeyframePoses& m, std::string* error) {
  if (!valid_robot(m.robot_id(), error)) return std::nullopt;
  if (m.seqs().size() != m.T_local_base().size()) {
    fail(error, "keyframe_poses: " + std::to_string(m.seqs().size()) + " seqs but " +
                    std::to_string(m.T_local_base().size()) + " poses");
    return std::nullopt;
  }
  KeyframePoses out{RobotId(m.robot_id()), m.stamp_ns(), {}};
  for (size_t i = 0; i < m.seqs().size(); ++i) {
    if (!finite_pose(m.T_local_base()[i])) {
      fail(error, "keyframe_poses: non-finite T_local_base of seq " + std::to_string(m.seqs()[i]));
      return std::nullopt;
    }
    out.poses.push_back(KeyframePose{m.seqs()[i], from_to_msg(m.T_local_base()[i])});
  }
  return out;
}

cairn_msgs::Keyframe to_msg(const Keyframe& kf) {
  cairn_msgs::Keyframe m;
  m.robot_id(kf.id.robot.value);
  m.seq(kf.id.seq);
  m.stamp_ns(kf.stamp_ns);
  m.T_local_base(to_msg(kf.T_local_base));
  std::array<double, 9> cov, ecov;
  Eigen::Map<Eigen::Matrix<double, 3, 3, Eigen::RowMajor>>(cov.data()) = kf.covariance;
  Eigen::Map<Eigen::Matrix<double, 3, 3, Eigen::RowMajor>>(ecov.data()) = kf.edge_covariance;
  m.covariance(cov);
  m.T_prev_this(to_msg(kf.T_prev_this));
  m.edge_covariance(ecov);
  m.scan_zstd(encode_scan(kf.scan));
  m.place_descriptor_zstd(encode_scan_context(kf.place_descriptor));
  for (const LandmarkObservation& o : kf.landmarks) {
    cairn_msgs::LandmarkObservation l;
    l.landmark_id(o.id.value);
    l.stamp_ns(o.stamp_ns);
    l.range_m(float(o.range_m));
    l.bearing_rad(float(o.bearing_rad));
    l.sigma_range_m(float(o.sigma_range_m));
    l.sigma_bearing_rad(float(o.sigma_bearing_rad));
    m.landmarks().push_back(l);
  }
  for (const SalientPoint& p : kf.salient) {
    cairn_msgs::SalientPoint q;
    q.x_m(p.x_m);
    q.y_m(p.y_m);
    q.weight(p.weight);
    m.salient().push_back(q);
  }
  return m;
}

std::optional<Keyframe> from_msg(const cairn_msgs::Keyframe& m, std::string* error) {
  if (!valid_robot(m.robot_id(), error)) return std::nullopt;
  if (m.seq() < 0) {
    fail(error, "keyframe: negative seq");
    return std::nullopt;
  }
  if (!finite_pose(m.T_local_base()) || !finite_pose(m.T_prev_this())) {
    fail(error, "keyframe: non-finite T_local_base or T_prev_this");
    return std::nullopt;
  }
  if (!all_finite(m.covariance()) || !all_finite(m.edge_covariance())) {
    fail(error, "keyframe: non-finite covariance");
    return std::nullopt;
  }
  std::string scan_error;
  auto scan = decode_scan(m.scan_zstd(), &scan_error);
  if (!scan) {
    fail(error, "keyframe: scan_zstd: " + scan_error);
    return std::nullopt;
  }
  Keyframe kf;
  kf.id = {RobotId(m.robot_id()), m.seq()};
  kf.stamp_ns = m.stamp_ns();
  kf.T_local_base = from_to_msg(m.T_local_base());
  kf.covariance = Eigen::Map<const Eigen::Matrix<double, 3, 3, Eigen::RowMajor>>(m.covariance().data());
  kf.T_prev_this = from_to_msg(m.T_prev_this());
  kf.edge_covariance = Eigen::Map<const Eigen::Matrix<double, 3, 3, Eigen::RowMajor>>(m.edge_covariance().data());
  kf.scan = std::move(*scan);
  kf.scan.stamp_ns = kf.stamp_ns;
  auto descriptor = decode_scan_context(m.place_descriptor_zstd(), &scan_error);
  if (!descriptor) {
    fail(error, "keyframe: place_descriptor_zstd: " + scan_error);
    return std::nullopt;
  }
  kf.place_descriptor = std::move(*descriptor);
  for (size_t i = 0; i < m.landmarks().size(); ++i) {
    const cairn_msgs::LandmarkObservation& l = m.landmarks()[i];
    const LandmarkObservation o{LandmarkId(l.landmark_id()), l.stamp_ns(),         l.range_m(), l.bearing_rad(),
                                l.sigma_range_m(),           l.sigma_bearing_rad()};
    const std::string bad = validate_landmark_observation(o);
    if (!bad.empty()) {
      fail(error, "keyframe: landmarks[" + std::to_string(i) + "]: " + bad);
      return std::nullopt;
    }
    kf.landmarks.push_back(o);
  }
  for (size_t i = 0; i < m.salient().size(); ++i) {
    const cairn_msgs::SalientPoint& q = m.salient()[i];
    if (!std::isfinite(q.x_m()) || !std::isfinite(q.y_m()) || !(q.weight() >= 0.f && q.weight() <= 1.f)) {
      fail(error, "keyframe: salient[" + std::to_string(i) + "]: non-finite position or weight outside 0..1");
      return std::nullopt;
    }
    kf.salient.push_back(SalientPoint{q.x_m(), q.y_m(), q.weight()});
  }
  return kf;
}

cairn_msgs::ObjectReport to_msg(const ObjectReport& o) {
  cairn_msgs::ObjectReport m;
  m.robot_id(o.id.robot.value);
  m.object_seq(o.id.seq);
  m.class_name(o.class_name);
  m.confidence(o.confidence);
  m.stamp_ns(o.stamp_ns);
  m.anchor_seq(o.anchor_seq);
  m.T_anchor_object(iso_to_array(o.T_anchor_object));
  std::array<double, 36> cov;
  Eigen::Map<Eigen::Matrix<double, 6, 6, Eigen::RowMajor>>(cov.data()) = o.covariance;
  m.covariance(cov);
  m.observations(o.observations);
  m.size_m({o.size_m.x(), o.size_m.y(), o.size_m.z()});
  m.point_count(int32_t(o.cloud.size()));
  m.cloud_zstd(encode_cloud(o.cloud));
  m.thumbnail_jpeg(o.thumbnail_jpeg);
  return m;
}

std::optional<ObjectReport> from_msg(const cairn_msgs::ObjectReport& m, std::string* error) {
  if (!valid_robot(m.robot_id(), error)) return std::nullopt;
  if (m.object_seq() < 0 || m.anchor_seq() < 0) {
    fail(error, "object: negative object_seq or anchor_seq");
    return std::nullopt;
  }
  if (m.class_name().empty() || m.class_name().size() > 64) {
    fail(error, "object: class_name empty or longer than 64 characters");
    return std::nullopt;
  }
  if (!std::isfinite(m.confidence()) || m.confidence() < 0.f || m.confidence() > 1.f) {
    fail(error, "object: confidence outside [0, 1]");
    return std::nullopt;
  }
  auto T = array_to_iso(m.T_anchor_object());
  if (!T) {
    fail(error, "object: T_anchor_object is not a finite rigid transform");
    return std::nullopt;
  }
  if (!all_finite(m.covariance())) {
    fail(error, "object: non-finite covariance");
    return std::nullopt;
  }
  std::string cloud_error;
  auto cloud = decode_cloud(m.cloud_zstd(), &cloud_error);
  if (!cloud) {
    fail(error, "object: cloud_zstd: " + cloud_error);
    return std::nullopt;
  }
  ObjectReport o;
  o.id = {RobotId(m.robot_id()), m.object_seq()};
  o.class_name = m.class_name();
  o.confidence = m.confidence();
  o.stamp_ns = m.stamp_ns();
  o.anchor_seq = m.anchor_seq();
  o.T_anchor_object = *T;
  o.covariance = Eigen::Map<const Eigen::Matrix<double, 6, 6, Eigen::RowMajor>>(m.covariance().data());
  o.observations = m.observations();
  o.size_m = {m.size_m()[0], m.size_m()[1], m.size_m()[2]};
  o.cloud = std::move(*cloud);
  o.thumbnail_jpeg = m.thumbnail_jpeg();
  return o;
}

}  // namespace cairn::dds
