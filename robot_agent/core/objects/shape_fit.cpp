#include "robot_agent/core/objects/shape_fit.h"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>

namespace cairn::agent {

const char* to_string(ShapeKind kind) {
  switch (kind) {
    case ShapeKind::kBox:
      return "box";
    case ShapeKind::kCylinder:
      return "cylinder";
    case ShapeKind::kSphere:
      return "sphere";
    default:
      return "unknown";
  }
}

namespace {

void z_extent(const std::vector<Eigen::Vector3d>& pts, double* lo, double* hi) {
  *lo = 1e300, *hi = -1e300;
  for (const auto& p : pts) *lo = std::min(*lo, p.z()), *hi = std::max(*hi, p.z());
}

}  // namespace

ShapeFit fit_sphere(const std::vector<Eigen::Vector3d>& pts, const ShapeFitOptions& o) {
  ShapeFit f;
  f.kind = ShapeKind::kSphere;
  if (int(pts.size()) < o.min_points) return f.reason = "too few points", f;
  Eigen::MatrixXd A(pts.size(), 4);
  Eigen::VectorXd y(pts.size());
  const Eigen::Vector3d mean = [&] {
    Eigen::Vector3d m = Eigen::Vector3d::Zero();
    for (auto& p : pts) m += p;
    return Eigen::Vector3d(m / double(pts.size()));
  }();
  for (size_t i = 0; i < pts.size(); ++i) {
    const Eigen::Vector3d p = pts[i] - mean;
    A.row(Eigen::Index(i)) << 2 * p.x(), 2 * p.y(), 2 * p.z(), 1.0;
    y(Eigen::Index(i)) = p.squaredNorm();
  }
  const Eigen::Vector4d s = A.colPivHouseholderQr().solve(y);
  const double r2 = s(3) + s.head<3>().squaredNorm();
  if (!(r2 > 0.0) || !s.allFinite()) return f.reason = "degenerate sphere fit", f;
  const double r = std::sqrt(r2);
  f.center_m = mean + s.head<3>();
  f.size_m = Eigen::Vector3d::Constant(2 * r);
  double sq = 0.0;
  for (const auto& p : pts) sq += std::pow((p - f.center_m).norm() - r, 2);
  f.score = std::sqrt(sq / double(pts.size()));
  f.converged = r >= o.min_radius_m && r <= o.max_radius_m;
  if (!f.converged) f.reason = "implausible sphere radius";
  return f;
}

ShapeFit fit_vertical_cylinder(const std::vector<Eigen::Vector3d>& pts, const ShapeFitOptions& o) {
  ShapeFit f;
  f.kind = ShapeKind::kCylinder;
  if (int(pts.size()) < o.min_points) return f.reason = "too few points", f;
  Eigen::Vector2d mean = Eigen::Vector2d::Zero();
  for (const auto& p : pts) mean += p.head<2>();
  mean /= double(pts.size());
  Eigen::MatrixXd A(pts.size(), 3);
  Eigen::VectorXd y(pts.size());
  for (size_t i = 0; i < pts.size(); ++i) {
    const Eigen::Vector2d p = pts[i].head<2>() - mean;
    A.row(Eigen::Index(i)) << 2 * p.x(), 2 * p.y(), 1.0;
    y(Eigen::Index(i)) = p.squaredNorm();
  }
  const Eigen::Vector3d s = A.colPivHouseholderQr().solve(y);
  const double r2 = s(2) + s.head<2>().squaredNorm();
  if (!(r2 > 0.0) || !s.allFinite()) return f.reason = "degenerate circle fit", f;
  const double r = std::sqrt(r2);
  double lo, hi;
  z_extent(pts, &lo, &hi);
  f.center_m << mean + s.head<2>(), 0.5 * (lo + hi);
  f.size_m << 2 * r, 2 * r, hi - lo;
  double sq = 0.0;
  for (const auto& p : pts) sq += std::pow((p.head<2>() - f.center_m.head<2>()).norm() - r, 2);
  f.score = std::sqrt(sq / double(pts.size()));
  f.converged = r >= o.min_radius_m && r <= o.max_radius_m;
  if (!f.converged) f.reason = "implausible cylinder radius";
  return f;
}

ShapeFit fit_box(const std::vector<Eigen::Vector3d>& pts, const ShapeFitOptions& o) {
  ShapeFit f;
  f.kind = ShapeKind::kBox;
  if (int(pts.size()) < o.min_points) return f.reason = "too few points", f;
  auto extents = [&](double yaw, Eigen::Vector2d* lo, Eigen::Vector2d* hi) {
    const double c = std::cos(yaw), s = std::sin(yaw);
    *lo = Eigen::Vector2d::Constant(1e300), *hi = -*lo;
    for (const auto& p : pts) {
      const Eigen::Vector2d q(c * p.x() + s * p.y(), -s * p.x() + c * p.y());
      *lo = lo->cwiseMin(q), *hi = hi->cwiseMax(q);
    }
  };
  // Yaw by the closeness criterion of L-shape fitting (Zhang et al., "Efficient L-shape fitting
  // for vehicle detection using laser scanners", 2017): the visible side faces should lie on the
  // rectangle's edges. The minimum-area rectangle is wrong for a thin L (one long and one short
  // visible face): it aligns with the L's hypotenuse. Top-face points are interior, so only the
  // side points vote; seen from above (few side points) every point does.
  double zlo0, zhi0;
  z_extent(pts, &zlo0, &zhi0);
  std::vector<Eigen::Vector2d> side;
  for (const auto& p : pts)
    if (p.z() < zhi0 - o.top_face_band_m) side.push_back(p.head<2>());
  if (int(side.size()) < o.min_points) {
    side.clear();
    for (const auto& p : pts) side.push_back(p.head<2>());
  }
  double best_closeness = -1.0;
  Eigen::Vector2d lo, hi;
  for (int k = 0; k < 90; ++k) {  // 1 degree steps over the rectangle's symmetry period
    const double yaw = k * M_PI / 180.0, c = std::cos(yaw), s = std::sin(yaw);
    Eigen::Vector2d slo = Eigen::Vector2d::Constant(1e300), shi = -slo;
    std::vector<Eigen::Vector2d> q(side.size());
    for (size_t i = 0; i < side.size(); ++i) {
      q[i] = Eigen::Vector2d(c * side[i].x() + s * side[i].y(), -s * side[i].x() + c * side[i].y());
      slo = slo.cwiseMin(q[i]), shi = shi.cwiseMax(q[i]);
    }
    double closeness = 0.0;
    for (const Eigen::Vector2d& p : q) {
      const double dx = std::min(p.x() - slo.x(), shi.x() - p.x()), dy = std::min(p.y() - slo.y(), shi.y() - p.y());
      closeness += 1.0 / std::max(std::min(dx, dy), o.closeness_floor_m);
    }
    if (closeness > best_closeness) best_closeness = closeness, f.yaw_rad = yaw;
  }
  extents(f.yaw_rad, &lo, &hi);
  const Eigen::Vector2d mid = 0.5 * (lo + hi);
  const double c = std::cos(f.yaw_rad), s = std::sin(f.yaw_rad);
  double zlo, zhi;
  z_extent(pts, &zlo, &zhi);
  f.center_m << c * mid.x() - s * mid.y(), s * mid.x() + c * mid.y(), 0.5 * (zlo + zhi);
  f.size_m << hi - lo, zhi - zlo;
  // Residual: distance to the nearest footprint side or to the top face.
  double sq = 0.0;
  for (const auto& p : pts) {
    const Eigen::Vector2d q(c * p.x() + s * p.y(), -s * p.x() + c * p.y());
    const double d = std::min({q.x() - lo.x(), hi.x() - q.x(), q.y() - lo.y(), hi.y() - q.y(), zhi - p.z()});
    sq += d * d;
  }
  f.score = std::sqrt(sq / double(pts.size()));
  f.converged = true;
  return f;
}

void complete_box_footprint(ShapeFit* f, const Eigen::Vector3d& viewpoint, const ShapeFitOptions& o) {
  const Eigen::Vector2d prior = o.box_footprint_prior_m;
  if (f->kind != ShapeKind::kBox || !f->converged || !(prior.minCoeff() > 0.0)) return;
  const double L = prior.maxCoeff(), S = prior.minCoeff();
  const Eigen::Vector2d fitted = f->size_m.head<2>();
  // Assignment a: x <- L, y <- S; b: x <- S, y <- L. The side closest to the short prior side takes
  // it (an end face seen alone is the short side), unless a fitted side would overshoot its prior.
  auto cost = [&](double px, double py) {
    const double short_fitted = px < py ? fitted.x() : fitted.y();
    return 10.0 * (std::max(0.0, fitted.x() - px) + std::max(0.0, fitted.y() - py)) + std::abs(short_fitted - S);
  };
  const Eigen::Vector2d target = cost(L, S) <= cost(S, L) ? Eigen::Vector2d(L, S) : Eigen::Vector2d(S, L);
  const double c = std::cos(f->yaw_rad), s = std::sin(f->yaw_rad);
  const Eigen::Vector2d axes[2] = {Eigen::Vector2d(c, s), Eigen::Vector2d(-s, c)};
  const Eigen::Vector2d view = (f->center_m - viewpoint).head<2>();
  if (view.norm() < 1e-6) return;
  for (int k = 0; k < 2; ++k) {
    const double missing = target[k] - fitted[k];
    const double along = view.normalized().dot(axes[k]);
    // The other side must be (nearly) complete: it is what identifies the hidden one.
    const bool other_complete = fitted[1 - k] >= (1.0 - o.completion_side_tolerance) * target[1 - k];
    if (missing <= 0.0 || !other_complete || f->score > o.max_completion_rms_m ||
        std::abs(along) < o.min_completion_view_cos)
      continue;
    f->center_m.head<2>() += 0.5 * missing * (along > 0 ? 1.0 : -1.0) * axes[k];
    f->size_m[k] = target[k];
  }
}

ShapeFit best_shape_fit(const std::vector<Eigen::Vector3d>& pts, const Eigen::Vector3d& viewpoint,
                        const ShapeFitOptions& o) {
  ShapeFit best = fit_box(pts, o);
  if (!best.converged) return best;
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  for (const auto& p : pts) mean += p;
  mean /= double(pts.size());
  const Eigen::Vector2d view = (mean - viewpoint).head<2>().normalized();
  for (const ShapeFit& f : {fit_vertical_cylinder(pts, o), fit_sphere(pts, o)}) {
    if (!f.converged) continue;
    // A convex primitive's centre lies behind its visible surface, seen from the camera.
    if ((f.center_m - mean).head<2>().dot(view) < 0.0) continue;
    if (f.score + o.box_preference_m < best.score) best = f;
  }
  complete_box_footprint(&best, viewpoint, o);
  return best;
}

}  // namespace cairn::agent
