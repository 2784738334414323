#include "robot_agent/core/ceres_scan_matcher.h"

#include <ceres/ceres.h>
#include <ceres/cubic_interpolation.h>

#include <algorithm>
#include <cmath>
#include <memory>
#if defined(__SSE2__)
#include <emmintrin.h>
#endif

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

// Ceres' CubicHermiteSpline (Catmull-Rom) for one dimension.
inline void hermite(double p0, double p1, double p2, double p3, double x, double* f, double* dfdx) {
  const double a = 0.5 * (-p0 + 3.0 * p1 - 3.0 * p2 + p3);
  const double b = 0.5 * (2.0 * p0 - 5.0 * p1 + 4.0 * p2 - p3);
  const double c = 0.5 * (-p0 + p2);
  *f = p1 + x * (c + x * (b + x * a));
  *dfdx = c + x * (2.0 * b + 3.0 * a * x);
}

// 1 - v / 255 for every field byte v (the cost the interpolator reads; the same double as computing it).
struct FieldCostTable {
  double cost[256];
  FieldCostTable() {
    constexpr double k = 1.0 / 255.0;
    for (int v = 0; v < 256; ++v) cost[v] = 1.0 - v * k;
  }
};
const FieldCostTable kFieldCost;

#if defined(__SSE2__)
// hermite() on two lanes at once (the same operations in the same order per lane: bit-identical).
inline void hermite2(__m128d p0, __m128d p1, __m128d p2, __m128d p3, __m128d x, __m128d* f, __m128d* dfdx) {
  const __m128d half = _mm_set1_pd(0.5), two = _mm_set1_pd(2.0), three = _mm_set1_pd(3.0), four = _mm_set1_pd(4.0),
                five = _mm_set1_pd(5.0);
  const __m128d np0 = _mm_xor_pd(p0, _mm_set1_pd(-0.0));
  const __m128d a =
      _mm_mul_pd(half, _mm_add_pd(_mm_sub_pd(_mm_add_pd(np0, _mm_mul_pd(three, p1)), _mm_mul_pd(three, p2)), p3));
  const __m128d b = _mm_mul_pd(
      half, _mm_sub_pd(_mm_add_pd(_mm_sub_pd(_mm_mul_pd(two, p0), _mm_mul_pd(five, p1)), _mm_mul_pd(four, p2)), p3));
  const __m128d c = _mm_mul_pd(half, _mm_add_pd(np0, p2));
  *f = _mm_add_pd(p1, _mm_mul_pd(x, _mm_add_pd(c, _mm_mul_pd(x, _mm_add_pd(b, _mm_mul_pd(x, a))))));
  if (dfdx) *dfdx = _mm_add_pd(c, _mm_mul_pd(x, _mm_add_pd(_mm_mul_pd(two, b), _mm_mul_pd(_mm_mul_pd(three, a), x))));
}
#endif

// ceres::BiCubicInterpolator<CostGridAdapter>::Evaluate for the likelihood field, reading the 4x4
// neighbourhood straight from the field bytes when it lies inside the grid (the same arithmetic,
// without 16 bounds-checked virtual-free but opaque GetValue calls). SSE2: two rows per vector.
inline bool bicubic_field(const ProbabilityGrid& grid, double r, double c, double* f, double* dfdr, double* dfdc) {
  const int row = int(std::floor(r)), col = int(std::floor(c));
  if (row < 1 || col < 1 || row + 2 >= grid.height() || col + 2 >= grid.width()) return false;
  const int w = grid.width();
  const uint8_t* p = grid.field().data() + size_t(row - 1) * w + (col - 1);
  const double x = c - col, y = r - row;
  const double* cost = kFieldCost.cost;
#if defined(__SSE2__)
  const uint8_t* q = p + 2 * size_t(w);
  const __m128d vx = _mm_set1_pd(x);
  __m128d f01, d01, f23, d23;
  hermite2(_mm_set_pd(cost[p[w]], cost[p[0]]), _mm_set_pd(cost[p[w + 1]], cost[p[1]]),
           _mm_set_pd(cost[p[w + 2]], cost[p[2]]), _mm_set_pd(cost[p[w + 3]], cost[p[3]]), vx, &f01, &d01);
  hermite2(_mm_set_pd(cost[q[w]], cost[q[0]]), _mm_set_pd(cost[q[w + 1]], cost[q[1]]),
           _mm_set_pd(cost[q[w + 2]], cost[q[2]]), _mm_set_pd(cost[q[w + 3]], cost[q[3]]), vx, &f23, &d23);
  // Lane 0: the row values fr[], lane 1: their x derivatives dfr[].
  const __m128d p0 = _mm_unpacklo_pd(f01, d01), p1 = _mm_unpackhi_pd(f01, d01);
  const __m128d p2 = _mm_unpacklo_pd(f23, d23), p3 = _mm_unpackhi_pd(f23, d23);
  __m128d fy, dfy;
  hermite2(p0, p1, p2, p3, _mm_set1_pd(y), &fy, &dfy);
  *f = _mm_cvtsd_f64(fy);
  *dfdc = _mm_cvtsd_f64(_mm_unpackhi_pd(fy, fy));
  *dfdr = _mm_cvtsd_f64(dfy);
#else
  double fr[4], dfr[4];
  for (int i = 0; i < 4; ++i, p += w) {
    hermite(cost[p[0]], cost[p[1]], cost[p[2]], cost[p[3]], x, &fr[i], &dfr[i]);
  }
  double unused;
  hermite(fr[0], fr[1], fr[2], fr[3], y, f, dfdr);
  hermite(dfr[0], dfr[1], dfr[2], dfr[3], y, dfdc, &unused);
#endif
  return true;
}

// The bicubic value alone on the probabilities (interpolated_score), reading the cells directly
// when the 4x4 neighbourhood is inside the grid; the same arithmetic as CostGridAdapter + Ceres.
inline bool bicubic_probability(const ProbabilityGrid& grid, double r, double c, double* f) {
  const int row = int(std::floor(r)), col = int(std::floor(c));
  if (row < 1 || col < 1 || row + 2 >= grid.height() || col + 2 >= grid.width()) return false;
  const int w = grid.width();
  const uint16_t* p = grid.values().data() + size_t(row - 1) * w + (col - 1);
  const double x = c - col, y = r - row;
  double fr[4], unused;
  for (int i = 0; i < 4; ++i, p += w) {
    hermite(1.0 - double(grid.probability_of(p[0])), 1.0 - double(grid.probability_of(p[1])),
            1.0 - double(grid.probability_of(p[2])), 1.0 - double(grid.probability_of(p[3])), x, &fr[i], &unused);
  }
  hermite(fr[0], fr[1], fr[2], fr[3], y, f, &unused);
  return true;
}

// Residual_i = scale * (1 - P(R(yaw) p_i + t)), P the bicubic-interpolated probability grid
// (Cartographer's OccupiedSpaceCostFunction2D) or likelihood field, with an analytic Jacobian (the
// interpolator is evaluated once per point in double, returning the value and its gradient).
class OccupiedSpaceAnalyticCost : public ceres::CostFunction {
 public:
  OccupiedSpaceAnalyticCost(double scale, const std::vector<Eigen::Vector2f>& points, const ProbabilityGrid& grid,
                            bool field)
      : scale_(scale), points_(points), grid_(grid), field_(field), adapter_(grid, field), interpolator_(adapter_) {
    set_num_residuals(int(points.size()));
    mutable_parameter_block_sizes()->push_back(3);
  }

  // Ceres evaluates every accepted step twice at the same pose: residuals only (the candidate's
  // cost), then with the Jacobian. Each evaluation computes both and keeps them, so the second is
  // a copy (the same numbers).
  bool Evaluate(double const* const* parameters, double* residuals, double** jacobians) const override {
    const double* pose = parameters[0];
    double* J = jacobians ? jacobians[0] : nullptr;
    const size_t n = points_.size();
    if (!(cached_ && pose[0] == cached_pose_[0] && pose[1] == cached_pose_[1] && pose[2] == cached_pose_[2])) {
      cached_residuals_.resize(n);
      cached_jacobian_.resize(3 * n);
      evaluate(pose, cached_residuals_.data(), cached_jacobian_.data());
      std::copy_n(pose, 3, cached_pose_);
      cached_ = true;
    }
    std::copy_n(cached_residuals_.data(), n, residuals);
    if (J) std::copy_n(cached_jacobian_.data(), 3 * n, J);
    return true;
  }

 private:
  void evaluate(const double* pose, double* residuals, double* J) const {
    const double c = std::cos(pose[2]), s = std::sin(pose[2]);
    const double inv_res = 1.0 / grid_.resolution_m();
    const double ox = grid_.origin_m().x(), oy = grid_.origin_m().y();
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
      const double gx = scale_ * df_dcol * inv_res, gy = scale_ * df_drow * inv_res;
      J[3 * i + 0] = gx;
      J[3 * i + 1] = gy;
      J[3 * i + 2] = -gx * ry + gy * rx;
    }
  }

  mutable bool cached_ = false;
  mutable double cached_pose_[3] = {0.0, 0.0, 0.0};
  mutable std::vector<double> cached_residuals_, cached_jacobian_;
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

// Gauss-Newton covariance of the occupied-space residuals: sigma^2 (J^T J)^-1 with unscaled residuals,
// from the cost function's analytic Jacobian evaluated directly (no Ceres program and CRS matrix).
Covariance3 hessian_covariance(const ceres::CostFunction& cost, const double* pose, double scale,
                               const CeresScanMatcherOptions& options) {
  Covariance3 floor = Covariance3::Zero();
  floor.diagonal() << options.min_translation_variance_m2, options.min_translation_variance_m2,
      options.min_rotation_variance_rad2;
  const int n = cost.num_residuals();
  if (n < 4) return floor * 100.0;
  std::vector<double> residuals(static_cast<size_t>(n)), jacobian(static_cast<size_t>(n) * 3);
  const double* parameters[1] = {pose};
  double* jacobians[1] = {jacobian.data()};
  if (!cost.Evaluate(parameters, residuals.data(), jacobians)) return floor * 100.0;
  // The same numbers as reading them back through ceres::Problem::Evaluate (bit-identical result).
  const Eigen::MatrixXd J =
      Eigen::Map<const Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor>>(jacobian.data(), n, 3) / scale;
  double ss = 0.0;
  for (double v : residuals) ss += (v / scale) * (v / scale);
  const double sigma2 = ss / double(n - 3);
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
  // OccupiedSpaceCost's arithmetic (the same values), interior cells read directly.
  const CostGridAdapter adapter(grid, false);
  const ceres::BiCubicInterpolator<CostGridAdapter> interpolator(adapter);
  const double c = std::cos(T.yaw()), s = std::sin(T.yaw());
  const double inv_res = 1.0 / grid.resolution_m();
  const double ox = grid.origin_m().x(), oy = grid.origin_m().y();
  double sum = 0.0;
  for (const Eigen::Vector2f& p : points) {
    const double px = p.x(), py = p.y();
    const double wx = c * px - s * py + T.x();
    const double wy = s * px + c * py + T.y();
    const double col = (wx - ox) * inv_res - 0.5;
    const double row = (wy - oy) * inv_res - 0.5;
    double r;
    if (!bicubic_probability(grid, row, col, &r)) interpolator.Evaluate(row, col, &r);
    sum += 1.0 - r;
  }
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
  problem.AddResidualBlock(occ, nullptr, pose);
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
  out.converged =
      summary.IsSolutionUsable() && std::isfinite(pose[0]) && std::isfinite(pose[1]) && std::isfinite(pose[2]);
  if (!out.converged) {
    out.reason = "ceres: " + summary.message;
    out.pose = initial;
  }
  out.score = interpolated_score(out.pose, points, grid);
  if (options_.compute_covariance) out.covariance = hessian_covariance(*occ, pose, scale, options_);
  return out;
}

}  // namespace cairn::agent
