#include "robot_agent/core/ceres_scan_matcher.h"

#include <ceres/ceres.h>
#include <ceres/cubic_interpolation.h>

#include <cmath>
#include <memory>

namespace cairn::agent {
namespace {

// Grid2D adapter for ceres::BiCubicInterpolator: value (row, col) = 1 - probability of that cell,
// integer coordinates are cell centres; outside the grid the cost is that of unknown space.
class CostGridAdapter {
 public:
  enum { DATA_DIMENSION = 1 };
  CostGridAdapter(const ProbabilityGrid& grid, bool field) : grid_(grid), field_(field) {}
  void GetValue(int row, int col, double* f) const {
    *f = 1.0 - double(field_ ? grid_.field_at(col, row) : grid_.at(col, row, grid_.fill_probability()));
  }

 private:
  const ProbabilityGrid& grid_;
  const bool field_;
};

// Residual_i = scale * (1 - P(R(yaw) p_i + t)), P the bicubic-interpolated probability grid
// (Cartographer's OccupiedSpaceCostFunction2D) or likelihood field.
class OccupiedSpaceCost {
 public:
  OccupiedSpaceCost(double scale, const std::vector<Eigen::Vector2f>& points, const ProbabilityGrid& grid, bool field)
      : scale_(scale), points_(points), grid_(grid), adapter_(grid, field), interpolator_(adapter_) {}

  template <typename T>
  bool operator()(const T* const pose, T* residual) const {
    const T c = ceres::cos(pose[2]), s = ceres::sin(pose[2]);
    const T inv_res = T(1.0 / grid_.resolution_m());
    for (size_t i = 0; i < points_.size(); ++i) {
      const T px = T(double(points_[i].x())), py = T(double(points_[i].y()));
      const T wx = c * px - s * py + pose[0];
      const T wy = s * px + c * py + pose[1];
      const T col = (wx - T(grid_.origin_m().x())) * inv_res - T(0.5);
      const T row = (wy - T(grid_.origin_m().y())) * inv_res - T(0.5);
      interpolator_.Evaluate(row, col, &residual[i]);
      residual[i] = T(scale_) * residual[i];
    }
    return true;
  }

 private:
  const double scale_;
  const std::vector<Eigen::Vector2f>& points_;
  const ProbabilityGrid& grid_;
  const CostGridAdapter adapter_;
  const ceres::BiCubicInterpolator<CostGridAdapter> interpolator_;
};

// Ceres' CubicHermiteSpline (Catmull-Rom) for one dimension.
inline void hermite(double p0, double p1, double p2, double p3, double x, double* f, double* dfdx) {
  const double a = 0.5 * (-p0 + 3.0 * p1 - 3.0 * p2 + p3);
  const double b = 0.5 * (2.0 * p0 - 5.0 * p1 + 4.0 * p2 - p3);
  const double c = 0.5 * (-p0 + p2);
  *f = p1 + x * (c + x * (b + x * a));
  *dfdx = c + x * (2.0 * b + 3.0 * a * x);
}

// ceres::BiCubicInterpolator<CostGridAdapter>::Evaluate for the likelihood field, reading the 4x4
// neighbourhood straight from the field bytes when it lies inside the grid (the same arithmetic,
// without 16 bounds-checked virtual-free but opaque GetValue calls).
inline bool bicubic_field(const ProbabilityGrid& grid, double r, double c, double* f, double* dfdr, double* dfdc) {
  const int row = int(std::floor(r)), col = int(std::floor(c));
  if (row < 1 || col < 1 || row + 2 >= grid.height() || col + 2 >= grid.width()) return false;
  const int w = grid.width();
  const uint8_t* p = grid.field().data() + size_t(row - 1) * w + (col - 1);
  const double x = c - col, y = r - row;
  double fr[4], dfr[4];
  constexpr double k = 1.0 / 255.0;
  for (int i = 0; i < 4; ++i, p += w) {
    hermite(1.0 - p[0] * k, 1.0 - p[1] * k, 1.0 - p[2] * k, 1.0 - p[3] * k, x, &fr[i], &dfr[i]);
  }
  double unused;
  hermite(fr[0], fr[1], fr[2], fr[3], y, f, dfdr);
  hermite(dfr[0], dfr[1], dfr[2], dfr[3], y, dfdc, &unused);
  return true;
}

// The same residuals with an analytic Jacobian (no Jets: the interpolator is evaluated once per
// point in double, returning the value and its gradient).
class OccupiedSpaceAnalyticCost : public ceres::CostFunction {
 public:
  OccupiedSpaceAnalyticCost(double scale, const std::vector<Eigen::Vector2f>& points, const ProbabilityGrid& grid,
                            bool field)
      : scale_(scale), points_(points), grid_(grid), field_(field), adapter_(grid, field), interpolator_(adapter_) {
    set_num_residuals(int(points.size()));
    mutable_parameter_block_sizes()->push_back(3);
  }

  bool Evaluate(double const* const* parameters, double* residuals, double** jacobians) const override {
    const double* pose = parameters[0];
    const double c = std::cos(pose[2]), s = std::sin(pose[2]);
    const double inv_res = 1.0 / grid_.resolution_m();
    const double ox = grid_.origin_m().x(), oy = grid_.origin_m().y();
    double* J = jacobians ? jacobians[0] : nullptr;
    for (size_t i = 0; i < points_.size(); ++i) {
      const double px = points_[i].x(), py = points_[i].y();
      const double rx = c * px - s * py, ry = s * px + c * py;
      const double col = (rx + pose[0] - ox) * inv_res - 0.5;
      const double row = (ry + pose[1] - oy) * inv_res - 0.5;
      double f, df_drow, df_dcol;
      if (!field_ || !bicubic_field(grid_, row, col, &f, &df_drow, &df_dcol)) {
        interpolator_.Evaluate(row, col, &f, &df_drow, &df_dcol);
      }
      residuals[i] = scale_ * f;
      if (J) {
        const double gx = scale_ * df_dcol * inv_res, gy = scale_ * df_drow * inv_res;
        J[3 * i + 0] = gx;
        J[3 * i + 1] = gy;
        J[3 * i + 2] = -gx * ry + gy * rx;
      }
    }
    return true;
  }

 private:
  const double scale_;
  const std::vector<Eigen::Vector2f>& points_;
  const ProbabilityGrid& grid_;
  const bool field_;
  const CostGridAdapter adapter_;
  const ceres::BiCubicInterpolator<CostGridAdapter> interpolator_;
};

// Residual = weight * (t - t0) (Cartographer's TranslationDeltaCostFunctor2D).
struct TranslationDeltaCost {
  double weight, x0, y0;
  template <typename T>
  bool operator()(const T* const pose, T* residual) const {
    residual[0] = T(weight) * (pose[0] - T(x0));
    residual[1] = T(weight) * (pose[1] - T(y0));
    return true;
  }
};

// Residual = weight * (yaw - yaw0) (Cartographer's RotationDeltaCostFunctor2D).
struct RotationDeltaCost {
  double weight, yaw0;
  template <typename T>
  bool operator()(const T* const pose, T* residual) const {
    residual[0] = T(weight) * (pose[2] - T(yaw0));
    return true;
  }
};

// Gauss-Newton covariance of the occupied-space block: sigma^2 (J^T J)^-1 with unscaled residuals.
Covariance3 hessian_covariance(ceres::Problem* problem, ceres::ResidualBlockId block, double scale,
                               const CeresScanMatcherOptions& options) {
  ceres::Problem::EvaluateOptions eval;
  eval.residual_blocks = {block};
  std::vector<double> residuals;
  ceres::CRSMatrix jac;
  Covariance3 floor = Covariance3::Zero();
  floor.diagonal() << options.min_translation_variance_m2, options.min_translation_variance_m2,
      options.min_rotation_variance_rad2;
  if (!problem->Evaluate(eval, nullptr, &residuals, nullptr, &jac) || jac.num_rows < 4) return floor * 100.0;
  Eigen::MatrixXd J = Eigen::MatrixXd::Zero(jac.num_rows, jac.num_cols);
  for (int r = 0; r < jac.num_rows; ++r) {
    for (int k = jac.rows[r]; k < jac.rows[r + 1]; ++k) J(r, jac.cols[k]) = jac.values[k] / scale;
  }
  double ss = 0.0;
  for (double v : residuals) ss += (v / scale) * (v / scale);
  const double sigma2 = ss / double(jac.num_rows - 3);
  Eigen::Matrix3d H = J.transpose() * J;
  // A degenerate direction (a straight corridor: no gradient along it) makes H singular; a tiny
  // ridge keeps that direction's variance large instead of failing over to an isotropic guess.
  H.diagonal().array() += 1e-9 * std::max(1e-12, H.trace());
  Eigen::FullPivLU<Eigen::Matrix3d> lu(H);
  if (!lu.isInvertible()) return floor * 100.0;
  Covariance3 cov = sigma2 * lu.inverse();
  cov = 0.5 * (cov + cov.transpose());
  return cov + floor;
}

}  // namespace

CeresScanMatcher::CeresScanMatcher(const CeresScanMatcherOptions& options) : options_(options) {}

double interpolated_score(const SE2& T, const std::vector<Eigen::Vector2f>& points, const ProbabilityGrid& grid) {
  if (points.empty()) return 0.0;
  OccupiedSpaceCost cost(1.0, points, grid, false);
  std::vector<double> residuals(points.size());
  const double pose[3] = {T.x(), T.y(), T.yaw()};
  cost(pose, residuals.data());
  double sum = 0.0;
  for (double r : residuals) sum += 1.0 - r;
  return sum / double(points.size());
}

CeresMatch CeresScanMatcher::match(const SE2& initial, const std::vector<Eigen::Vector2f>& points,
                                   const ProbabilityGrid& grid) const {
  CeresMatch out;
  out.pose = initial;
  if (points.empty() || grid.width() == 0) {
    out.reason = "no points or empty grid";
    return out;
  }
  double pose[3] = {initial.x(), initial.y(), initial.yaw()};
  ceres::Problem problem;
  const double scale = options_.occupied_space_weight / std::sqrt(double(points.size()));
  auto* occ = new OccupiedSpaceAnalyticCost(scale, points, grid, options_.use_likelihood_field);
  const ceres::ResidualBlockId occ_block = problem.AddResidualBlock(occ, nullptr, pose);
  problem.AddResidualBlock(new ceres::AutoDiffCostFunction<TranslationDeltaCost, 2, 3>(
                               new TranslationDeltaCost{options_.translation_weight, pose[0], pose[1]}),
                           nullptr, pose);
  problem.AddResidualBlock(new ceres::AutoDiffCostFunction<RotationDeltaCost, 1, 3>(
                               new RotationDeltaCost{options_.rotation_weight, pose[2]}),
                           nullptr, pose);
  ceres::Solver::Options solver_options;
  solver_options.linear_solver_type = ceres::DENSE_QR;
  solver_options.max_num_iterations = options_.max_num_iterations;
  solver_options.num_threads = 1;
  solver_options.logging_type = ceres::SILENT;
  solver_options.minimizer_progress_to_stdout = false;
  ceres::Solver::Summary summary;
  ceres::Solve(solver_options, &problem, &summary);
  out.pose = SE2(pose[0], pose[1], pose[2]);
  out.converged = summary.IsSolutionUsable() && std::isfinite(pose[0]) && std::isfinite(pose[1]) &&
                  std::isfinite(pose[2]);
  if (!out.converged) {
    out.reason = "ceres: " + summary.message;
    out.pose = initial;
  }
  out.score = interpolated_score(out.pose, points, grid);
  out.covariance = hessian_covariance(&problem, occ_block, scale, options_);
  return out;
}

}  // namespace cairn::agent
