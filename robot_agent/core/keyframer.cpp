#include "robot_agent/core/keyframer.h"

#include <cmath>

namespace cairn::agent {

Covariance3 compose_covariance(const SE2& A, const Covariance3& cov_A, const SE2& B, const Covariance3& cov_B) {
  const Eigen::Vector2d t = A.rotation() * B.translation();
  Eigen::Matrix3d J_A = Eigen::Matrix3d::Identity();
  J_A(0, 2) = -t.y();
  J_A(1, 2) = t.x();
  Eigen::Matrix3d J_B = Eigen::Matrix3d::Identity();
  J_B.topLeftCorner<2, 2>() = A.rotation();
  return J_A * cov_A * J_A.transpose() + J_B * cov_B * J_B.transpose();
}

Keyframer::Keyframer(RobotId robot, const KeyframerOptions& options) : robot_(robot), options_(options) {}

bool Keyframer::should_emit(StampNs stamp_ns, const SE2& pose) const {
  if (!last_) return true;
  const SE2 d = last_->T_local_base.between(pose);
  return d.translation().norm() > options_.min_distance_m || std::abs(d.yaw()) > options_.min_angle_rad ||
         ns_to_sec(stamp_ns - last_->stamp_ns) > options_.max_interval_s;
}

std::optional<Keyframe> Keyframer::add(const LaserScan& scan, const SE2& T_local_base, const Covariance3& covariance) {
  if (!should_emit(scan.stamp_ns, T_local_base)) return std::nullopt;
  Covariance3 edge = Covariance3::Zero();
  if (last_) {
    // Both ends were matched against the local map independently; express both in the prev frame.
    const SE2 d = last_->T_local_base.between(T_local_base);
    Eigen::Matrix3d rot = Eigen::Matrix3d::Identity();
    rot.topLeftCorner<2, 2>() = last_->T_local_base.rotation().transpose();
    edge += rot * (last_match_covariance_ + covariance) * rot.transpose();
    const double dist_m = d.translation().norm(), angle_rad = std::abs(d.yaw());
    edge(0, 0) += options_.edge_translation_floor_m2 + options_.edge_translation_variance_per_m * dist_m;
    edge(1, 1) += options_.edge_translation_floor_m2 + options_.edge_translation_variance_per_m * dist_m;
    edge(2, 2) += options_.edge_rotation_floor_rad2 + options_.edge_rotation_variance_per_rad * angle_rad;
  }
  Keyframe kf = emit(scan, T_local_base, last_ ? edge : covariance);
  last_match_covariance_ = covariance;
  return kf;
}

std::optional<Keyframe> Keyframer::add_dead_reckoned(StampNs stamp_ns, const SE2& T_local_base,
                                                     const Covariance3& odometry_covariance) {
  if (!should_emit(stamp_ns, T_local_base)) return std::nullopt;
  LaserScan no_scan;
  no_scan.stamp_ns = stamp_ns;
  Covariance3 edge = odometry_covariance;
  if (last_) {
    Eigen::Matrix3d rot = Eigen::Matrix3d::Identity();
    rot.topLeftCorner<2, 2>() = last_->T_local_base.rotation().transpose();
    edge += rot * last_match_covariance_ * rot.transpose();
  }
  // The matched edges' floors: wheels are never surer than that (turning in place they slip), and a
  // robot turning in place got 1e-18 m^2 along (nothing driven), information 4e17 at the base, whose
  // pose graph then could not converge after linking it (CI: a robot left 6 m off).
  edge(0, 0) += options_.edge_translation_floor_m2;
  edge(1, 1) += options_.edge_translation_floor_m2;
  edge(2, 2) += options_.edge_rotation_floor_rad2;
  Keyframe kf = emit(no_scan, T_local_base, edge);
  last_match_covariance_ = Covariance3::Zero();  // nothing was matched
  return kf;
}

Keyframe Keyframer::emit(const LaserScan& scan, const SE2& T_local_base, const Covariance3& edge_covariance) {
  Keyframe kf;
  kf.id = KeyframeId{robot_, next_seq_++};
  kf.stamp_ns = scan.stamp_ns;
  kf.T_local_base = T_local_base;
  kf.scan = scan;  // laser at the base origin: the scan is already in the base frame
  if (!last_) {
    kf.T_prev_this = SE2();
    kf.covariance = edge_covariance;
  } else {
    kf.T_prev_this = last_->T_local_base.between(T_local_base);
    kf.edge_covariance = 0.5 * (edge_covariance + edge_covariance.transpose());
    kf.covariance = compose_covariance(last_->T_local_base, last_->covariance, kf.T_prev_this, kf.edge_covariance);
  }
  last_ = kf;
  return kf;
}

}  // namespace cairn::agent
