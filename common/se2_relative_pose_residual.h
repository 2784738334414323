#pragma once
// The SE2 relative-pose residual of every pose graph in Cairn: the robot agent's submap graph
// (agent::SubmapPoseGraph) and the base station's keyframe graph (base::KeyframePoseGraph). It is the
// "sparse pose adjustment" edge (Konolige et al. 2010; Ceres' pose_graph_2d example; Cartographer's
// SpaCostFunction2D), header-only and templated for ceres::AutoDiffCostFunction. Include it only in
// the .cpp files that build a Ceres problem.
#include <ceres/autodiff_cost_function.h>
#include <ceres/jet.h>

#include <Eigen/Core>
#include <cmath>

#include "common/se2.h"

namespace cairn {

/// Wraps an angle to [-pi, pi) with floor; on doubles and Ceres Jets (derivative 1).
template <typename T>
T wrap_angle_floor(const T& a_rad) {
  const T two_pi(2.0 * M_PI);
  return a_rad - two_pi * ceres::floor((a_rad + T(M_PI)) / two_pi);
}

/// Wraps an angle to (-pi, pi] exactly as cairn::normalize_angle (std::fmod) does. On a Jet the
/// value is normalize_angle's and the derivative passes through (1).
inline double wrap_angle_fmod(double a_rad) { return normalize_angle(a_rad); }
template <int N>
ceres::Jet<double, N> wrap_angle_fmod(const ceres::Jet<double, N>& a_rad) {
  return ceres::Jet<double, N>(normalize_angle(a_rad.a), a_rad.v);
}

/// How the yaw error is wrapped onto the circle. The two give the same angle except at +-pi and in
/// the last bit (fmod's shift by pi and back rounds; floor leaves an in-range angle untouched), so
/// each graph keeps the one its results were produced with:
enum class YawWrap {
  kFmod,   ///< (-pi, pi], cairn::normalize_angle (as SE2 wraps): agent::SubmapPoseGraph
  kFloor,  ///< [-pi, pi), floor (as its yaw manifold wraps): base::KeyframePoseGraph
};

/// Relative-pose error of an edge a -> b measured as z = T_a_b; poses a, b = (x, y, yaw) in one
/// frame. Residual (3), the error in a's frame weighted after it is formed:
///   r = L * [ R(yaw_a)^T (p_b - p_a) - p_z ;  wrap(yaw_b - yaw_a - yaw_z) ]
/// with L the edge's square-root information (row i of r = sum_k L(i,k) e_k). The agent passes
/// diag(w_t, w_t, w_r) (fixed 1/sigma weights) or a scan match's anisotropic L; the base passes the
/// upper-triangular LLT factor of the edge's information matrix.
class Se2RelativePoseResidual {
 public:
  Se2RelativePoseResidual(const SE2& T_a_b, const Eigen::Matrix3d& sqrt_information, YawWrap wrap)
      : p_ab_(T_a_b.translation()), yaw_ab_rad_(T_a_b.yaw()), sqrt_information_(sqrt_information), wrap_(wrap) {}

  /// Fixed weights: L = diag(translation_weight, translation_weight, rotation_weight) (1/m, 1/rad).
  static Eigen::Matrix3d diagonal_sqrt_information(double translation_weight, double rotation_weight) {
    return Eigen::Vector3d(translation_weight, translation_weight, rotation_weight).asDiagonal();
  }

  /// The residual as a Ceres cost function with automatic derivatives (Ceres owns the functor).
  static ceres::CostFunction* create(const SE2& T_a_b, const Eigen::Matrix3d& sqrt_information, YawWrap wrap) {
    return new ceres::AutoDiffCostFunction<Se2RelativePoseResidual, 3, 3, 3>(
        new Se2RelativePoseResidual(T_a_b, sqrt_information, wrap));
  }

  template <typename T>
  bool operator()(const T* a, const T* b, T* residual) const {
    const T c = ceres::cos(a[2]), s = ceres::sin(a[2]);
    const T dx = b[0] - a[0], dy = b[1] - a[1];
    const T dyaw = b[2] - a[2] - T(yaw_ab_rad_);
    Eigen::Matrix<T, 3, 1> e;
    e(0) = c * dx + s * dy - T(p_ab_.x());
    e(1) = -s * dx + c * dy - T(p_ab_.y());
    e(2) = wrap_ == YawWrap::kFmod ? wrap_angle_fmod(dyaw) : wrap_angle_floor(dyaw);
    Eigen::Map<Eigen::Matrix<T, 3, 1>> r(residual);
    r = sqrt_information_.template cast<T>() * e;
    return true;
  }

 private:
  Eigen::Vector2d p_ab_;
  double yaw_ab_rad_;
  Eigen::Matrix3d sqrt_information_;
  YawWrap wrap_;
};

}  // namespace cairn
