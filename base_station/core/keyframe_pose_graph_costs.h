#pragma once
// The cost functions of KeyframePoseGraph besides the shared SE2 relative-pose residual
// (common/se2_relative_pose_residual.h): the yaw manifold, the SE-Sync edge, the pose prior and the
// range-bearing observation of a point node, with the helpers that build their weights and losses.
// Internal to keyframe_pose_graph*.cpp (Ceres headers stay out of keyframe_pose_graph.h).
#include <ceres/ceres.h>

#include <Eigen/Cholesky>
#include <cmath>
#include <optional>

#include "base_station/core/keyframe_pose_graph.h"
#include "common/se2_relative_pose_residual.h"

namespace cairn::base::keyframe_pose_graph_costs {

/// A node (x, y, yaw): x, y Euclidean, yaw on the circle (x + delta wrapped, y - x the shortest
/// signed arc), as Ceres 2.1 AutoDiffManifold.
struct PoseManifold {
  template <typename T>
  bool Plus(const T* x, const T* delta, T* x_plus_delta) const {
    x_plus_delta[0] = x[0] + delta[0];
    x_plus_delta[1] = x[1] + delta[1];
    x_plus_delta[2] = wrap_angle_floor(x[2] + delta[2]);
    return true;
  }
  template <typename T>
  bool Minus(const T* y, const T* x, T* y_minus_x) const {
    y_minus_x[0] = y[0] - x[0];
    y_minus_x[1] = y[1] - x[1];
    y_minus_x[2] = wrap_angle_floor(y[2] - x[2]);
    return true;
  }
};

/// SE-Sync's per-edge objective (Rosen et al. 2019) for 2D, so that sum r^2 equals it:
/// Residual (3): [ sqrt(tau) (R_a^T (p_b - p_a) - p_ab) ; sqrt(8 kappa) sin(wrap(yaw_b - yaw_a - yaw_ab) / 2) ]
/// (||R_b - R_a R_ab||_F^2 = 4 (1 - cos e) = 8 sin^2(e / 2); the translation norm is rotation-invariant).
struct SeSyncResidual {
  SeSyncResidual(const SE2& T_a_b, const Eigen::Matrix3d& information)
      : p_ab_(T_a_b.translation()),
        yaw_ab_rad_(T_a_b.yaw()),
        sqrt_tau_(std::sqrt(2.0 / information.topLeftCorner<2, 2>().inverse().trace())),
        sqrt_8kappa_(std::sqrt(8.0 * information(2, 2))) {}

  template <typename T>
  bool operator()(const T* a, const T* b, T* r) const {
    const T c = ceres::cos(a[2]), s = ceres::sin(a[2]);
    const T dx = b[0] - a[0], dy = b[1] - a[1];
    r[0] = T(sqrt_tau_) * (c * dx + s * dy - T(p_ab_.x()));
    r[1] = T(sqrt_tau_) * (-s * dx + c * dy - T(p_ab_.y()));
    r[2] = T(sqrt_8kappa_) * ceres::sin(wrap_angle_floor(b[2] - a[2] - T(yaw_ab_rad_)) / T(2.0));
    return true;
  }

  Eigen::Vector2d p_ab_;
  double yaw_ab_rad_, sqrt_tau_, sqrt_8kappa_;
};

/// Absolute prior on one node.
/// Residual (3): sqrt_info * [ p - p_prior ; wrap(yaw - yaw_prior) ] (errors in the world frame).
struct PriorResidual {
  PriorResidual(const SE2& T_world_node, const Eigen::Matrix3d& sqrt_information)
      : p_(T_world_node.translation()), yaw_rad_(T_world_node.yaw()), sqrt_information_(sqrt_information) {}

  template <typename T>
  bool operator()(const T* pose, T* residual) const {
    Eigen::Matrix<T, 3, 1> e;
    e(0) = pose[0] - T(p_.x());
    e(1) = pose[1] - T(p_.y());
    e(2) = wrap_angle_floor(pose[2] - T(yaw_rad_));
    Eigen::Map<Eigen::Matrix<T, 3, 1>> r(residual);
    r = sqrt_information_.template cast<T>() * e;
    return true;
  }

  Eigen::Vector2d p_;
  double yaw_rad_;
  Eigen::Matrix3d sqrt_information_;
};

/// Range-bearing observation of a landmark point l from pose a.
/// Residual (2): [ (|d| - range) / sigma_range ; wrap(atan2(d_y, d_x) - bearing) / sigma_bearing ],
/// d = R_a^T (l - p_a) (the landmark in a's frame).
struct RangeBearingResidual {
  explicit RangeBearingResidual(const LandmarkEdge& e) : e_(e) {}

  template <typename T>
  bool operator()(const T* a, const T* l, T* residual) const {
    const T c = ceres::cos(a[2]), s = ceres::sin(a[2]);
    const T dx = l[0] - a[0], dy = l[1] - a[1];
    const T x = c * dx + s * dy, y = -s * dx + c * dy;
    residual[0] = (ceres::sqrt(x * x + y * y + T(1e-12)) - T(e_.range_m)) / T(e_.sigma_range_m);
    residual[1] = wrap_angle_floor(ceres::atan2(y, x) - T(e_.bearing_rad)) / T(e_.sigma_bearing_rad);
    return true;
  }

  LandmarkEdge e_;
};

/// Upper-triangular R with R^T R = information (the example's LLT square root).
inline std::optional<Eigen::Matrix3d> sqrt_information(const Eigen::Matrix3d& information) {
  if (!information.allFinite()) return std::nullopt;
  const Eigen::Matrix3d sym = 0.5 * (information + information.transpose());
  Eigen::LLT<Eigen::Matrix3d> llt(sym);
  if (llt.info() != Eigen::Success) return std::nullopt;
  return Eigen::Matrix3d(llt.matrixL().transpose());
}

inline ceres::LossFunction* make_loss(const RobustLossOptions& o) {
  switch (o.type) {
    case RobustLossType::kHuber:
      return new ceres::HuberLoss(o.scale);
    case RobustLossType::kCauchy:
      return new ceres::CauchyLoss(o.scale);
    case RobustLossType::kNone:
      break;
  }
  return nullptr;
}

}  // namespace cairn::base::keyframe_pose_graph_costs
