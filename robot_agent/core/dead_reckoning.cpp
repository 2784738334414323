#include "robot_agent/core/dead_reckoning.h"

#include <cmath>
#include <stdexcept>

#include "robot_agent/core/keyframer.h"

namespace cairn::agent {

DeadReckoning::DeadReckoning(const DeadReckoningOptions& options) : options_(options) {
  if (!(options.laser_timeout_s > 0) || !(options.step_interval_s > 0) ||
      !(options.translation_variance_m2_per_m >= 0) || !(options.rotation_variance_rad2_per_m >= 0) ||
      !(options.rotation_variance_rad2_per_rad >= 0)) {
    throw std::invalid_argument("DeadReckoningOptions: timeout and step must be > 0, variances >= 0");
  }
}

void DeadReckoning::start(const SE2& T_local_base, const SE2& T_odom_base) {
  T_local_base_ = T_local_base;
  T_odom_base_ = T_odom_base;
  keyframe_emitted();
}

const SE2& DeadReckoning::advance(const SE2& T_odom_base) {
  const SE2 step = T_odom_base_.between(T_odom_base);
  T_odom_base_ = T_odom_base;
  T_local_base_ = T_local_base_ * step;
  // The step's own noise, in the robot's frame before it, propagated with the earlier uncertainty.
  const double d_m = step.translation().norm(), a_rad = std::abs(step.yaw());
  Covariance3 q = Covariance3::Zero();
  q(0, 0) = q(1, 1) = options_.translation_variance_m2_per_m * d_m;
  q(2, 2) = options_.rotation_variance_rad2_per_m * d_m + options_.rotation_variance_rad2_per_rad * a_rad;
  covariance_ = compose_covariance(T_keyframe_base_, covariance_, step, q);
  T_keyframe_base_ = T_keyframe_base_ * step;
  return T_local_base_;
}

void DeadReckoning::keyframe_emitted() {
  T_keyframe_base_ = SE2();
  covariance_ = Covariance3::Zero();
}

}  // namespace cairn::agent
