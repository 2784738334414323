#include "base_station/core/pcm.h"

#include <Eigen/Cholesky>
#include <algorithm>

namespace cairn::base {
namespace {

Eigen::Matrix3d leg_covariance(const SE2& T_leg, const PcmOptions& o) {
  const double d = T_leg.translation().norm();
  const double sxy = o.odometry_sigma_xy_floor_m + o.odometry_sigma_xy_per_m * d;
  const double syaw = o.odometry_sigma_yaw_floor_rad + o.odometry_sigma_yaw_rad_per_m * d;
  return Eigen::Vector3d(sxy * sxy, sxy * sxy, syaw * syaw).asDiagonal();
}

/// Rotates a covariance over (x, y, yaw) into another frame by yaw_rad.
Eigen::Matrix3d rotate(const Eigen::Matrix3d& cov, double yaw_rad) {
  Eigen::Matrix3d R = Eigen::Matrix3d::Identity();
  R.topLeftCorner<2, 2>() = Eigen::Rotation2Dd(yaw_rad).toRotationMatrix();
  return R * cov * R.transpose();
}

/// Bron-Kerbosch with pivoting; keeps the largest clique found.
void bron_kerbosch(std::vector<size_t>& r, std::vector<size_t> p, std::vector<size_t> x,
                   const std::vector<std::vector<bool>>& adj, std::vector<size_t>* best) {
  if (p.empty() && x.empty()) {
    if (r.size() > best->size()) *best = r;
    return;
  }
  if (r.size() + p.size() <= best->size()) return;
  size_t pivot = p.empty() ? x.front() : p.front();
  size_t pivot_degree = 0;
  for (const auto* set : {&p, &x}) {
    for (size_t u : *set) {
      size_t deg = 0;
      for (size_t v : p) deg += adj[u][v];
      if (deg >= pivot_degree) {
        pivot_degree = deg;
        pivot = u;
      }
    }
  }
  const std::vector<size_t> candidates = p;
  for (size_t v : candidates) {
    if (adj[pivot][v]) continue;
    std::vector<size_t> p2, x2;
    for (size_t u : p)
      if (adj[v][u]) p2.push_back(u);
    for (size_t u : x)
      if (adj[v][u]) x2.push_back(u);
    r.push_back(v);
    bron_kerbosch(r, p2, x2, adj, best);
    r.pop_back();
    p.erase(std::find(p.begin(), p.end(), v));
    x.push_back(v);
  }
}

}  // namespace

bool pcm_consistent(const LoopClosure& i, const LoopClosure& j, const LocalPoseFn& local_pose, const PcmOptions& o) {
  const SE2 T_ai_aj = local_pose(i.a).between(local_pose(j.a));
  const SE2 T_bi_bj = local_pose(i.b).between(local_pose(j.b));
  // Two routes from a_i to b_j: via closure i then B's odometry, via A's odometry then closure j.
  const SE2 via_i = i.T_a_b * T_bi_bj;
  const SE2 via_j = T_ai_aj * j.T_a_b;
  const Eigen::Vector3d e = via_j.between(via_i).vector();
  // First-order covariance of the cycle, every leg expressed (approximately) in a_i's frame.
  Eigen::Matrix3d cov = i.covariance + rotate(leg_covariance(T_bi_bj, o), i.T_a_b.yaw()) +
                        rotate(j.covariance, T_ai_aj.yaw()) + leg_covariance(T_ai_aj, o);
  // The yaw uncertainty of the first leg moves the far end: add its lever arm.
  const double lever = (via_i.translation() - i.T_a_b.translation()).norm();
  cov(0, 0) += lever * lever * i.covariance(2, 2);
  cov(1, 1) += lever * lever * i.covariance(2, 2);
  const Eigen::Matrix3d cov_e = rotate(cov, -via_j.yaw());
  Eigen::LDLT<Eigen::Matrix3d> ldlt(cov_e);
  const double m2 = e.dot(ldlt.solve(e));
  return std::isfinite(m2) && m2 < o.chi2_threshold;
}

std::vector<size_t> pcm_max_clique(const std::vector<LoopClosure>& closures, const LocalPoseFn& local_pose,
                                   const PcmOptions& options) {
  const size_t n = closures.size();
  std::vector<std::vector<bool>> adj(n, std::vector<bool>(n, false));
  for (size_t i = 0; i < n; ++i) {
    for (size_t j = i + 1; j < n; ++j) {
      adj[i][j] = adj[j][i] = pcm_consistent(closures[i], closures[j], local_pose, options);
    }
  }
  std::vector<size_t> best, r, p(n), x;
  for (size_t i = 0; i < n; ++i) p[i] = i;
  if (n > 0) best = {0};
  bron_kerbosch(r, p, x, adj, &best);
  std::sort(best.begin(), best.end());
  return best;
}

}  // namespace cairn::base
