#include "robot_agent/core/pose_graph_2d.h"

#include <ceres/ceres.h>

#include <cmath>

namespace cairn::agent {
namespace {

// Residual (Cartographer's SpaCostFunction2D) = diag(w_t, w_t, w_r) * (z (-) (T_i^-1 T_j)) with
//   translation: R(yaw_i)^T (t_j - t_i) - t_z,   rotation: wrap(yaw_j - yaw_i - yaw_z),
// with its analytic Jacobians (cheaper than Jets: the graph is re-solved periodically).
class RelativePoseCost : public ceres::SizedCostFunction<3, 3, 3> {
 public:
  RelativePoseCost(const SE2& z, double w_t, double w_r) : x_(z.x()), y_(z.y()), yaw_(z.yaw()), w_t_(w_t), w_r_(w_r) {}
  static ceres::CostFunction* create(const SE2& z, double w_t, double w_r) { return new RelativePoseCost(z, w_t, w_r); }

  bool Evaluate(double const* const* p, double* r, double** J) const override {
    const double* a = p[0];
    const double* b = p[1];
    const double c = std::cos(a[2]), s = std::sin(a[2]);
    const double dx = b[0] - a[0], dy = b[1] - a[1];
    r[0] = w_t_ * (c * dx + s * dy - x_);
    r[1] = w_t_ * (-s * dx + c * dy - y_);
    r[2] = w_r_ * normalize_angle(b[2] - a[2] - yaw_);
    if (J == nullptr) return true;
    if (J[0] != nullptr) {
      double* Ja = J[0];  // row-major 3x3, d r / d (x_i, y_i, yaw_i)
      Ja[0] = -w_t_ * c; Ja[1] = -w_t_ * s; Ja[2] = w_t_ * (-s * dx + c * dy);
      Ja[3] = w_t_ * s;  Ja[4] = -w_t_ * c; Ja[5] = w_t_ * (-c * dx - s * dy);
      Ja[6] = 0.0;       Ja[7] = 0.0;       Ja[8] = -w_r_;
    }
    if (J[1] != nullptr) {
      double* Jb = J[1];  // d r / d (x_j, y_j, yaw_j)
      Jb[0] = w_t_ * c;  Jb[1] = w_t_ * s;  Jb[2] = 0.0;
      Jb[3] = -w_t_ * s; Jb[4] = w_t_ * c;  Jb[5] = 0.0;
      Jb[6] = 0.0;       Jb[7] = 0.0;       Jb[8] = w_r_;
    }
    return true;
  }

 private:
  double x_, y_, yaw_, w_t_, w_r_;
};

}  // namespace

PoseGraph2D::PoseGraph2D(const PoseGraphOptions& options) : options_(options) {}

int PoseGraph2D::add_submap(const SE2& T_global_submap) {
  submaps_.push_back(T_global_submap);
  return int(submaps_.size()) - 1;
}

int PoseGraph2D::add_node(const SE2& T_global_node, const SE2& T_local_node) {
  nodes_.push_back(T_global_node);
  local_nodes_.push_back(T_local_node);
  return int(nodes_.size()) - 1;
}

void PoseGraph2D::add_constraint(const PoseGraphConstraint& c) {
  constraints_.push_back(c);
  if (c.kind == PoseGraphConstraint::Kind::kLoopClosure) ++num_loops_;
}

bool PoseGraph2D::optimize(int max_num_iterations) {
  if (submaps_.empty() || nodes_.empty()) return true;
  std::vector<std::array<double, 3>> s(submaps_.size()), n(nodes_.size());
  for (size_t i = 0; i < submaps_.size(); ++i) s[i] = {submaps_[i].x(), submaps_[i].y(), submaps_[i].yaw()};
  for (size_t i = 0; i < nodes_.size(); ++i) n[i] = {nodes_[i].x(), nodes_[i].y(), nodes_[i].yaw()};
  ceres::Problem problem;
  const PoseGraphOptions& o = options_;
  for (const PoseGraphConstraint& c : constraints_) {
    const bool loop = c.kind == PoseGraphConstraint::Kind::kLoopClosure;
    problem.AddResidualBlock(
        RelativePoseCost::create(c.T_submap_node, loop ? o.loop_translation_weight : o.intra_translation_weight,
                                 loop ? o.loop_rotation_weight : o.intra_rotation_weight),
        loop ? new ceres::HuberLoss(o.loop_huber_scale) : nullptr, s[size_t(c.submap)].data(),
        n[size_t(c.node)].data());
  }
  for (size_t i = 1; i < nodes_.size(); ++i) {
    problem.AddResidualBlock(RelativePoseCost::create(local_nodes_[i - 1].between(local_nodes_[i]),
                                                      o.successive_translation_weight, o.successive_rotation_weight),
                             nullptr, n[i - 1].data(), n[i].data());
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
