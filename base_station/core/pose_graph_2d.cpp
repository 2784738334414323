#include "base_station/core/pose_graph_2d.h"

#include <ceres/ceres.h>

#include <Eigen/Cholesky>
#include <cmath>
#include <memory>

namespace cairn::base {
namespace {

/// Wraps an angle to [-pi, pi); works on doubles and Ceres Jets.
template <typename T>
T normalize_angle_t(const T& a_rad) {
  const T two_pi(2.0 * M_PI);
  return a_rad - two_pi * ceres::floor((a_rad + T(M_PI)) / two_pi);
}

/// Yaw lives on the circle: x + delta is wrapped, y - x is the shortest signed arc
/// (Ceres 2.1 AutoDiffManifold, the example's AngleManifold).
struct AngleManifold {
  template <typename T>
  bool Plus(const T* x_rad, const T* delta_rad, T* x_plus_delta_rad) const {
    *x_plus_delta_rad = normalize_angle_t(*x_rad + *delta_rad);
    return true;
  }
  template <typename T>
  bool Minus(const T* y_rad, const T* x_rad, T* y_minus_x_rad) const {
    *y_minus_x_rad = normalize_angle_t(*y_rad - *x_rad);
    return true;
  }
};

/// Relative-pose error of edge a -> b.
/// Residual (3): sqrt_info * [ R_a^T (p_b - p_a) - p_ab ;  wrap(yaw_b - yaw_a - yaw_ab) ].
struct RelativePoseResidual {
  RelativePoseResidual(const SE2& T_a_b, const Eigen::Matrix3d& sqrt_information)
      : p_ab_(T_a_b.translation()), yaw_ab_rad_(T_a_b.yaw()), sqrt_information_(sqrt_information) {}

  template <typename T>
  bool operator()(const T* xa, const T* ya, const T* yaw_a, const T* xb, const T* yb, const T* yaw_b,
                  T* residual) const {
    const T c = ceres::cos(*yaw_a), s = ceres::sin(*yaw_a);
    const T dx = *xb - *xa, dy = *yb - *ya;
    Eigen::Matrix<T, 3, 1> e;
    e(0) = c * dx + s * dy - T(p_ab_.x());
    e(1) = -s * dx + c * dy - T(p_ab_.y());
    e(2) = normalize_angle_t(*yaw_b - *yaw_a - T(yaw_ab_rad_));
    Eigen::Map<Eigen::Matrix<T, 3, 1>> r(residual);
    r = sqrt_information_.template cast<T>() * e;
    return true;
  }

  Eigen::Vector2d p_ab_;
  double yaw_ab_rad_;
  Eigen::Matrix3d sqrt_information_;
};

/// Absolute prior on one node.
/// Residual (3): sqrt_info * [ p - p_prior ; wrap(yaw - yaw_prior) ] (errors in the world frame).
struct PriorResidual {
  PriorResidual(const SE2& T_world_node, const Eigen::Matrix3d& sqrt_information)
      : p_(T_world_node.translation()), yaw_rad_(T_world_node.yaw()), sqrt_information_(sqrt_information) {}

  template <typename T>
  bool operator()(const T* x, const T* y, const T* yaw, T* residual) const {
    Eigen::Matrix<T, 3, 1> e;
    e(0) = *x - T(p_.x());
    e(1) = *y - T(p_.y());
    e(2) = normalize_angle_t(*yaw - T(yaw_rad_));
    Eigen::Map<Eigen::Matrix<T, 3, 1>> r(residual);
    r = sqrt_information_.template cast<T>() * e;
    return true;
  }

  Eigen::Vector2d p_;
  double yaw_rad_;
  Eigen::Matrix3d sqrt_information_;
};

/// Upper-triangular R with R^T R = information (the example's LLT square root).
std::optional<Eigen::Matrix3d> sqrt_information(const Eigen::Matrix3d& information) {
  if (!information.allFinite()) return std::nullopt;
  const Eigen::Matrix3d sym = 0.5 * (information + information.transpose());
  Eigen::LLT<Eigen::Matrix3d> llt(sym);
  if (llt.info() != Eigen::Success) return std::nullopt;
  return Eigen::Matrix3d(llt.matrixL().transpose());
}

bool finite(const SE2& T) { return T.vector().allFinite(); }

ceres::LossFunction* make_loss(const RobustLossOptions& o) {
  switch (o.type) {
    case RobustLossType::kHuber: return new ceres::HuberLoss(o.scale);
    case RobustLossType::kCauchy: return new ceres::CauchyLoss(o.scale);
    case RobustLossType::kNone: break;
  }
  return nullptr;
}

}  // namespace

const char* to_string(EdgeKind kind) {
  switch (kind) {
    case EdgeKind::kOdometry: return "odometry";
    case EdgeKind::kLoop: return "loop";
    case EdgeKind::kPrior: return "prior";
  }
  return "unknown";
}

PoseGraph2d::PoseGraph2d(const PoseGraphOptions& options) : options_(options) {}

bool PoseGraph2d::add_node(KeyframeId id, const SE2& T) {
  if (nodes_.count(id) || !finite(T)) return false;
  nodes_[id] = NodeState{T.x(), T.y(), T.yaw()};
  return true;
}

bool PoseGraph2d::set_estimate(KeyframeId id, const SE2& T) {
  auto it = nodes_.find(id);
  if (it == nodes_.end() || !finite(T)) return false;
  it->second = NodeState{T.x(), T.y(), T.yaw()};
  return true;
}

bool PoseGraph2d::add_edge(const PoseGraphEdge& edge) {
  if (edge.kind == EdgeKind::kPrior || edge.from == edge.to) return false;
  if (!nodes_.count(edge.from) || !nodes_.count(edge.to)) return false;
  if (!finite(edge.T_from_to) || !sqrt_information(edge.information)) return false;
  edges_.push_back(edge);
  return true;
}

bool PoseGraph2d::set_prior(const PosePrior& prior) {
  if (!nodes_.count(prior.node) || !finite(prior.T_world_node) || !sqrt_information(prior.information)) {
    return false;
  }
  priors_[prior.node] = prior;
  return true;
}

bool PoseGraph2d::remove_prior(KeyframeId id) { return priors_.erase(id) > 0; }

std::optional<SE2> PoseGraph2d::estimate(KeyframeId id) const {
  auto it = nodes_.find(id);
  if (it == nodes_.end()) return std::nullopt;
  return SE2(it->second.x_m, it->second.y_m, it->second.yaw_rad);
}

std::map<KeyframeId, SE2> PoseGraph2d::estimates() const {
  std::map<KeyframeId, SE2> out;
  for (const auto& [id, n] : nodes_) out.emplace(id, SE2(n.x_m, n.y_m, n.yaw_rad));
  return out;
}

PoseGraphSolveResult PoseGraph2d::solve(const PoseGraphSolveOptions& options) {
  PoseGraphSolveResult result;
  if (nodes_.empty()) {
    result.converged = true;
    result.reason = "empty graph";
    return result;
  }
  ceres::Problem problem;
  for (const PoseGraphEdge& e : edges_) {
    NodeState& a = nodes_.at(e.from);
    NodeState& b = nodes_.at(e.to);
    auto* cost = new ceres::AutoDiffCostFunction<RelativePoseResidual, 3, 1, 1, 1, 1, 1, 1>(
        new RelativePoseResidual(e.T_from_to, *sqrt_information(e.information)));
    const RobustLossOptions& loss = e.kind == EdgeKind::kLoop ? options_.loop_loss : options_.odometry_loss;
    problem.AddResidualBlock(cost, make_loss(loss), &a.x_m, &a.y_m, &a.yaw_rad, &b.x_m, &b.y_m, &b.yaw_rad);
  }
  for (const auto& [id, p] : priors_) {
    NodeState& n = nodes_.at(id);
    auto* cost = new ceres::AutoDiffCostFunction<PriorResidual, 3, 1, 1, 1>(
        new PriorResidual(p.T_world_node, *sqrt_information(p.information)));
    problem.AddResidualBlock(cost, make_loss(options_.prior_loss), &n.x_m, &n.y_m, &n.yaw_rad);
  }
  // Isolated nodes (no residual) are left out of the problem; add them so the gauge logic and
  // manifolds see a consistent set.
  for (auto& [id, n] : nodes_) {
    problem.AddParameterBlock(&n.x_m, 1);
    problem.AddParameterBlock(&n.y_m, 1);
    problem.AddParameterBlock(&n.yaw_rad, 1);
    problem.SetManifold(&n.yaw_rad, new ceres::AutoDiffManifold<AngleManifold, 1, 1>);
  }
  if (priors_.empty()) {
    NodeState& first = nodes_.begin()->second;
    problem.SetParameterBlockConstant(&first.x_m);
    problem.SetParameterBlockConstant(&first.y_m);
    problem.SetParameterBlockConstant(&first.yaw_rad);
  }
  ceres::Solver::Options so;
  so.max_num_iterations = options.max_iterations;
  so.function_tolerance = options.function_tolerance;
  so.gradient_tolerance = options.gradient_tolerance;
  so.parameter_tolerance = options.parameter_tolerance;
  so.linear_solver_type = ceres::SPARSE_NORMAL_CHOLESKY;
  so.num_threads = 1;
  so.logging_type = ceres::SILENT;
  so.minimizer_progress_to_stdout = false;
  ceres::Solver::Summary summary;
  ceres::Solve(so, &problem, &summary);
  for (auto& [id, n] : nodes_) n.yaw_rad = normalize_angle(n.yaw_rad);
  result.converged = summary.termination_type == ceres::CONVERGENCE;
  result.initial_cost = summary.initial_cost;
  result.final_cost = summary.final_cost;
  result.iterations = int(summary.iterations.size());
  result.reason = summary.message;
  return result;
}

}  // namespace cairn::base
