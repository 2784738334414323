#include "robot_agent/core/pose_graph_2d.h"

#include <ceres/ceres.h>

#include <Eigen/Eigenvalues>

#include <cmath>

namespace cairn::agent {
namespace {

// Residual (Cartographer's SpaCostFunction2D) = L * (z (-) (T_i^-1 T_j)), L = diag(w_t, w_t, w_r) or a
// full square-root information (anisotropic loop closures, see FullRelativePoseCost), with
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
      Ja[0] = -w_t_ * c;
      Ja[1] = -w_t_ * s;
      Ja[2] = w_t_ * (-s * dx + c * dy);
      Ja[3] = w_t_ * s;
      Ja[4] = -w_t_ * c;
      Ja[5] = w_t_ * (-c * dx - s * dy);
      Ja[6] = 0.0;
      Ja[7] = 0.0;
      Ja[8] = -w_r_;
    }
    if (J[1] != nullptr) {
      double* Jb = J[1];  // d r / d (x_j, y_j, yaw_j)
      Jb[0] = w_t_ * c;
      Jb[1] = w_t_ * s;
      Jb[2] = 0.0;
      Jb[3] = -w_t_ * s;
      Jb[4] = w_t_ * c;
      Jb[5] = 0.0;
      Jb[6] = 0.0;
      Jb[7] = 0.0;
      Jb[8] = w_r_;
    }
    return true;
  }

 private:
  double x_, y_, yaw_, w_t_, w_r_;
};

// The same error e with a full square-root information L: residual = L e, Jacobians L * de/dp.
class FullRelativePoseCost : public ceres::SizedCostFunction<3, 3, 3> {
 public:
  FullRelativePoseCost(const SE2& z, const Eigen::Matrix3d& L) : raw_(z, 1.0, 1.0), L_(L) {}

  bool Evaluate(double const* const* p, double* r, double** J) const override {
    double e[3], Ja[9], Jb[9];
    double* Jraw[2] = {Ja, Jb};
    raw_.Evaluate(p, e, J ? Jraw : nullptr);
    const Eigen::Map<const Eigen::Vector3d> ev(e);
    Eigen::Map<Eigen::Vector3d> rv(r);
    rv = L_ * ev;
    using RowMajor3 = Eigen::Matrix<double, 3, 3, Eigen::RowMajor>;
    for (int k = 0; J && k < 2; ++k) {
      if (J[k] == nullptr) continue;
      const Eigen::Map<const RowMajor3> jraw(Jraw[k]);
      Eigen::Map<RowMajor3> jout(J[k]);
      jout = L_ * jraw;
    }
    return true;
  }

 private:
  RelativePoseCost raw_;
  Eigen::Matrix3d L_;
};

}  // namespace

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

PoseGraph2D::PoseGraph2D(const PoseGraphOptions& options) : options_(options) {}

int PoseGraph2D::add_submap(const SE2& T_global_submap) {
  submaps_.push_back(T_global_submap);
  return int(submaps_.size()) - 1;
}

int PoseGraph2D::add_node(const SE2& T_global_node, const SE2& T_local_node,
                          const Eigen::Matrix3d* successive_sqrt_information) {
  nodes_.push_back(T_global_node);
  local_nodes_.push_back(T_local_node);
  has_successive_sqrt_information_.push_back(successive_sqrt_information != nullptr);
  successive_sqrt_information_.push_back(successive_sqrt_information ? *successive_sqrt_information
                                                                     : Eigen::Matrix3d::Identity());
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
    ceres::CostFunction* cost =
        c.has_sqrt_information
            ? static_cast<ceres::CostFunction*>(new FullRelativePoseCost(c.T_submap_node, c.sqrt_information))
            : RelativePoseCost::create(c.T_submap_node, loop ? o.loop_translation_weight : o.intra_translation_weight,
                                       loop ? o.loop_rotation_weight : o.intra_rotation_weight);
    problem.AddResidualBlock(cost, loop ? new ceres::HuberLoss(o.loop_huber_scale) : nullptr,
                             s[size_t(c.submap)].data(), n[size_t(c.node)].data());
  }
  for (size_t i = 1; i < nodes_.size(); ++i) {
    const SE2 z = local_nodes_[i - 1].between(local_nodes_[i]);
    ceres::CostFunction* cost =
        has_successive_sqrt_information_[i]
            ? static_cast<ceres::CostFunction*>(new FullRelativePoseCost(z, successive_sqrt_information_[i]))
            : RelativePoseCost::create(z, o.successive_translation_weight, o.successive_rotation_weight);
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
