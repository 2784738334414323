#pragma once
// Rigid transforms in the plane. Naming: T_a_b maps points from frame b into frame a, so
// T_a_c = T_a_b * T_b_c and p_a = T_a_b * p_b.
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cmath>

namespace cairn {

/// Wraps an angle to (-pi, pi].
inline double normalize_angle(double a_rad) {
  a_rad = std::fmod(a_rad + M_PI, 2.0 * M_PI);
  if (a_rad <= 0.0) a_rad += 2.0 * M_PI;
  return a_rad - M_PI;
}

class SE2 {
 public:
  SE2() = default;
  SE2(double x_m, double y_m, double yaw_rad) : t_(x_m, y_m), yaw_rad_(normalize_angle(yaw_rad)) {}
  SE2(const Eigen::Vector2d& t_m, double yaw_rad) : t_(t_m), yaw_rad_(normalize_angle(yaw_rad)) {}

  static SE2 identity() { return SE2(); }
  /// From a 3-vector (x_m, y_m, yaw_rad).
  static SE2 from_vector(const Eigen::Vector3d& v) { return SE2(v.x(), v.y(), v.z()); }

  double x() const { return t_.x(); }
  double y() const { return t_.y(); }
  double yaw() const { return yaw_rad_; }
  const Eigen::Vector2d& translation() const { return t_; }
  Eigen::Matrix2d rotation() const { return Eigen::Rotation2Dd(yaw_rad_).toRotationMatrix(); }
  Eigen::Vector3d vector() const { return {t_.x(), t_.y(), yaw_rad_}; }

  SE2 operator*(const SE2& o) const { return SE2(t_ + rotation() * o.t_, yaw_rad_ + o.yaw_rad_); }
  Eigen::Vector2d operator*(const Eigen::Vector2d& p) const { return t_ + rotation() * p; }
  SE2 inverse() const {
    const Eigen::Matrix2d Rt = rotation().transpose();
    return SE2(-(Rt * t_), -yaw_rad_);
  }
  /// The pose of `other` expressed in this frame: this^-1 * other.
  SE2 between(const SE2& other) const { return inverse() * other; }

  /// Lifts to a 3D transform (z = 0, rotation about z).
  Eigen::Isometry3d to_isometry3() const {
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    T.linear() = Eigen::AngleAxisd(yaw_rad_, Eigen::Vector3d::UnitZ()).toRotationMatrix();
    T.translation() = Eigen::Vector3d(t_.x(), t_.y(), 0.0);
    return T;
  }
  /// Projects a 3D transform to the plane (drops z, roll and pitch).
  static SE2 from_isometry3(const Eigen::Isometry3d& T) {
    const Eigen::Vector3d x_axis = T.linear().col(0);
    return SE2(T.translation().x(), T.translation().y(), std::atan2(x_axis.y(), x_axis.x()));
  }

  /// Linear interpolation of translation and shortest-arc interpolation of yaw.
  static SE2 interpolate(const SE2& a, const SE2& b, double s) {
    return SE2(a.t_ + s * (b.t_ - a.t_), a.yaw_rad_ + s * normalize_angle(b.yaw_rad_ - a.yaw_rad_));
  }

 private:
  Eigen::Vector2d t_ = Eigen::Vector2d::Zero();
  double yaw_rad_ = 0.0;
};

using Covariance3 = Eigen::Matrix3d;  ///< over (x_m, y_m, yaw_rad)

}  // namespace cairn
