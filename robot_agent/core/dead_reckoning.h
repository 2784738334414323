#pragma once
// Poses from wheel odometry alone, for a robot whose laser went silent (dust, smoke, a broken
// scanner): the pose moves with the odometry increments from where the laser last placed it, and
// the uncertainty since the last keyframe grows with the distance driven and the angle turned, so
// the keyframes built from it carry honest edge covariances. The noise model is the usual one for
// wheel odometry (and the simulator's, sim/sim_options.h OdometryOptions): variance growing linearly
// with travel, so that it does not depend on the odometry rate.
#include "common/se2.h"
#include "common/time.h"

namespace cairn::agent {

struct DeadReckoningOptions {
  /// No scan for this long (odometry time) while odometry goes on: the laser is lost.
  double laser_timeout_s = 1.0;
  /// A dead-reckoned pose this often (what navigation steers by and keyframes are cut from).
  double step_interval_s = 0.1;
  /// Odometry noise, variance per metre driven / per radian turned. The defaults are the simulated
  /// robots' (0.05 m, 0.02 rad per sqrt(m), 0.05 rad per sqrt(rad)); dead_reckoning_test.cpp checks
  /// that the covariance reported is the spread such noise gives. For a real robot, set them from the
  /// spread of its odometry against its laser SLAM over straight runs and turns on the spot.
  double translation_variance_m2_per_m = 0.05 * 0.05;
  double rotation_variance_rad2_per_m = 0.02 * 0.02;
  double rotation_variance_rad2_per_rad = 0.05 * 0.05;
};

class DeadReckoning {
 public:
  explicit DeadReckoning(const DeadReckoningOptions& options = {});

  /// Starts at `T_local_base`, where the odometry read `T_odom_base`; the uncertainty since the last
  /// keyframe starts at zero.
  void start(const SE2& T_local_base, const SE2& T_odom_base);
  /// Moves by the increment from the previous odometry reading to `T_odom_base`; the new pose.
  const SE2& advance(const SE2& T_odom_base);
  const SE2& pose() const { return T_local_base_; }
  /// Covariance of the pose relative to the last keyframe (or the start), in that keyframe's frame.
  const Covariance3& covariance_since_keyframe() const { return covariance_; }
  /// A keyframe was cut at the current pose: the uncertainty counts from here.
  void keyframe_emitted();
  const DeadReckoningOptions& options() const { return options_; }

 private:
  DeadReckoningOptions options_;
  SE2 T_local_base_, T_odom_base_;
  SE2 T_keyframe_base_;  ///< pose relative to the last keyframe
  Covariance3 covariance_ = Covariance3::Zero();
};

}  // namespace cairn::agent
