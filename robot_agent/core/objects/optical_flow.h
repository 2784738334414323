#pragma once
// Monocular optical-flow cues (seed paper Sec. 2.1, Eqs. 1-8, Algorithm 1): sparse pyramidal
// Lucas-Kanade flow between consecutive frames (OpenCV, inside optical_flow.cpp), the focus of
// expansion by least squares (Eq. 2: every flow vector points away from the FOE under pure
// translation), the time to contact tau = D / (dD/dt) (Eq. 3) per feature, and the collision test
// d_min < r (Eq. 8, second equality: the distance of a feature's 3D point from the robot's line of
// motion s, with the depth Z = tau * speed scaled by the odometry speed). Valid while the camera
// translates forward (speed > min_speed) and the yaw rate is small or compensated (rotation is
// removed with the odometry yaw rate); invalid when stopped, turning on the spot, or facing
// textureless walls. See docs/objects.md.
#include <Eigen/Core>
#include <memory>
#include <string>
#include <vector>

#include "common/sensors.h"

namespace cairn::agent {

struct FlowVector {
  Eigen::Vector2d p_px;     ///< position in the newer frame
  Eigen::Vector2d flow_px;  ///< displacement from the older frame to the newer one
};

struct FoeResult {
  Eigen::Vector2d foe_px = Eigen::Vector2d::Zero();
  bool converged = false;
  double score = 0.0;  ///< RMS perpendicular distance of the flow lines to the FOE, px
  int used = 0;
  std::string reason;
};

/// Least-squares point closest to all flow lines (p_i + t f_i): minimises sum (n_i . (foe - p_i))^2
/// with n_i the unit normal of f_i; vectors shorter than min_flow_px are ignored.
FoeResult estimate_foe(const std::vector<FlowVector>& flow, double min_flow_px = 0.3);

/// Time to contact of one feature (Eq. 3): tau = D / (dD/dt) with D its distance from the FOE;
/// dt_s the frame interval. Negative when the feature does not expand away from the FOE.
double time_to_contact_s(const FlowVector& f, const Eigen::Vector2d& foe_px, double dt_s);

/// Eq. 8, second equality: d_min = sqrt(x.x - (s.x)^2 / (s.s)), x the point, s the motion direction.
double closest_approach_m(const Eigen::Vector3d& point_camera, const Eigen::Vector3d& motion_dir_camera);

struct OpticalFlowOptions {
  int max_features = 150;
  double feature_quality = 0.01;
  double min_feature_distance_px = 8.0;
  int pyramid_levels = 3;
  int window_px = 21;
  double min_speed_mps = 0.05;        ///< below this the flow carries no depth
  double max_yaw_rate_radps = 0.6;    ///< beyond this the frame is skipped (rotation dominates)
  double robot_radius_m = 0.35;       ///< r of the collision test
  double horizon_s = 3.0;             ///< only contacts sooner than this are a risk
  int min_risky_features = 3;         ///< features with d_min < r and tau < horizon
  double min_foe_distance_px = 15.0;  ///< features this close to the FOE carry no usable tau
  double robust_percentile = 0.2;     ///< min_ttc_s / min_d_m are this percentile, not the minimum
};

struct CollisionEstimate {
  bool converged = false;  ///< a valid estimate this frame
  std::string reason;      ///< why not
  Eigen::Vector2d foe_px = Eigen::Vector2d::Zero();
  double min_ttc_s = -1.0;  ///< low percentile of the features' time to contact
  double min_d_m = -1.0;    ///< low percentile of d_min among features with tau < horizon
  int tracked = 0;
  int risky = 0;
  float collision_risk = 0.f;  ///< 0..1, for the status message
};

/// Algorithm 1 across frames: feed every RGB frame with the odometry speed and yaw rate.
class OpticalFlowCollision {
 public:
  explicit OpticalFlowCollision(const OpticalFlowOptions& options = {});
  ~OpticalFlowCollision();
  OpticalFlowCollision(OpticalFlowCollision&&) noexcept;
  OpticalFlowCollision& operator=(OpticalFlowCollision&&) noexcept;
  CollisionEstimate update(const RgbdFrame& frame, double speed_mps, double yaw_rate_radps);
  const CollisionEstimate& last() const { return last_; }

 private:
  struct State;
  OpticalFlowOptions options_;
  std::unique_ptr<State> state_;  ///< previous grey image (OpenCV types stay in the .cpp)
  CollisionEstimate last_;
};

/// The risk part of update(), usable without images (tests, other flow sources). K: intrinsics.
CollisionEstimate assess_collision(const std::vector<FlowVector>& flow, const CameraIntrinsics& K, double dt_s,
                                   double speed_mps, const OpticalFlowOptions& options);

}  // namespace cairn::agent
