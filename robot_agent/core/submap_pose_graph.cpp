#include "robot_agent/core/submap_pose_graph.h"

#include <ceres/ceres.h>

#include <Eigen/Eigenvalues>

#include <cmath>

#include "common/se2_relative_pose_residual.h"

namespace cairn::agent {

Eigen::Matrix3d anisotropic_sqrt_information(const Eigen::Matrix3d& covariance, double yaw_frame_match_rad,
                                             double translation_weight, double rotation_weight,
                                             double min_weight_ratio) {
  const double c = std::cos(yaw_frame_match_rad), s = std::sin(yaw_frame_match_rad);
  Eigen::Matrix2d R;
  R << c, -s, s, c;
  Eigen::Matrix2d C = R * covariance.topLeftCorner<2, 2>() * R.transpose();
  C = 0.5 * (C + C.transpose());
  Eigen::Matrix3d L = Eigen::Matrix3d::Zero();
  L(2, 2) = rotation_weight;
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> eig(C);
  const Eigen::Vector2d lambda = eig.eigenvalues();  // ascending
  if (eig.info() != Eigen::Success || !(lambda(0) > 0.0) || !std::isfinite(lambda(1))) {
    L(0, 0) = L(1, 1) = translation_weight;
    return L;
  }
  Eigen::Vector2d w;
  for (int i = 0; i < 2; ++i) w(i) = translation_weight * std::max(min_weight_ratio, std::sqrt(lambda(0) / lambda(i)));
  L.topLeftCorner<2, 2>() = eig.eigenvectors() * w.asDiagonal() * eig.eigenvectors().transpose();
  return L;
}

SubmapPoseGraph::SubmapPoseGraph(const SubmapPoseGraphOptions& options) : options_(options) {}

int SubmapPoseGraph::add_submap(const SE2& T_global_submap) {
  submaps_.push_back(T_global_submap);
  return int(submaps_.size()) - 1;
}

int SubmapPoseGraph::add_node(const SE2& T_global_node, const SE2& T_local_node,
                              const Eigen::Matrix3d* successive_sqrt_information) {
  nodes_.push_back(T_global_node);
  local_nodes_.push_back(T_local_node);
  has_successive_sqrt_information_.push_back(successive_sqrt_information != nullptr);
  successive_sqrt_information_.push_back(successive_sqrt_information ? *successive_sqrt_information
                                                                     : Eigen::Matrix3d::Identity());
  return int(nodes_.size()) - 1;
}

void SubmapPoseGraph::add_constraint(const SubmapPoseGraphConstraint& c) {
  constraints_.push_back(c);
  if (c.kind == SubmapPoseGraphConstraint::Kind::kLoopClosure) ++num_loops_;
}

bool SubmapPoseGraph::optimize(int max_num_iterations) {
  if (submaps_.empty() || nodes_.empty()) return true;
  std::vector<std::array<double, 3>> s(submaps_.size()), n(nodes_.size());
  for (size_t i = 0; i < submaps_.size(); ++i) s[i] = {submaps_[i].x(), submaps_[i].y(), submaps_[i].yaw()};
  for (size_t i = 0; i < nodes_.size(); ++i) n[i] = {nodes_[i].x(), nodes_[i].y(), nodes_[i].yaw()};
  ceres::Problem problem;
  const SubmapPoseGraphOptions& o = options_;
  for (const SubmapPoseGraphConstraint& c : constraints_) {
    const bool loop = c.kind == SubmapPoseGraphConstraint::Kind::kLoopClosure;
    const Eigen::Matrix3d L =
        c.has_sqrt_information ? c.sqrt_information
        : loop
            ? Se2RelativePoseResidual::diagonal_sqrt_information(o.loop_translation_weight, o.loop_rotation_weight)
            : Se2RelativePoseResidual::diagonal_sqrt_information(o.intra_translation_weight, o.intra_rotation_weight);
    ceres::CostFunction* cost = Se2RelativePoseResidual::create(c.T_submap_node, L, YawWrap::kFmod);
    problem.AddResidualBlock(cost, loop ? new ceres::HuberLoss(o.loop_huber_scale) : nullptr,
                             s[size_t(c.submap)].data(), n[size_t(c.node)].data());
  }
  for (size_t i = 1; i < nodes_.size(); ++i) {
    const SE2 z = local_nodes_[i - 1].between(local_nodes_[i]);
    const Eigen::Matrix3d L = has_successive_sqrt_information_[i]
                                  ? successive_sqrt_information_[i]
                                  : Se2RelativePoseResidual::diagonal_sqrt_information(o.successive_translation_weight,
                                                                                       o.successive_rotation_weight);
    ceres::CostFunction* cost = Se2RelativePoseResidual::create(z, L, YawWrap::kFmod);
    problem.AddResidualBlock(cost, nullptr, n[i - 1].data(), n[i].data());
  }
  problem.SetParameterBlockConstant(s[0].data());
  ceres::Solver::Options solver;
  solver.linear_solver_type = ceres::SPARSE_NORMAL_CHOLESKY;
  solver.max_num_iterations = max_num_iterations > 0 ? max_num_iterations : o.max_num_iterations;
  solver.num_threads = 1;
  solver.logging_type = ceres::SILENT;
  ceres::Solver::Summary summary;
  ceres::Solve(solver, &problem, &summary);
  if (!summary.IsSolutionUsable()) return false;
  for (size_t i = 0; i < submaps_.size(); ++i) submaps_[i] = SE2(s[i][0], s[i][1], s[i][2]);
  for (size_t i = 0; i < nodes_.size(); ++i) nodes_[i] = SE2(n[i][0], n[i][1], n[i][2]);
  return true;
}

}  // namespace cairn::agent
