#include "base_station/core/loop_verifier.h"

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <unordered_map>

namespace cairn::base {
namespace {

/// Likelihood grid L(cell) = max over map points of exp(-d^2 / 2 sigma^2), plus its max-pooled
/// precomputation grids: pooled[h](x, y) = max of L over [x, x + 2^h) x [y, y + 2^h).
struct PrecomputedGrids {
  Eigen::Vector2d origin_m;
  double resolution_m = 0.05;
  int width = 0, height = 0;
  std::vector<std::vector<float>> pooled;

  float at(int h, int x, int y) const {
    if (x < 0 || y < 0 || x >= width || y >= height) return 0.f;
    return pooled[size_t(h)][size_t(y) * width + x];
  }
};

PrecomputedGrids build_grids(const std::vector<Eigen::Vector2f>& map_points, const LoopVerifierOptions& o) {
  PrecomputedGrids g;
  g.resolution_m = o.resolution_m;
  Eigen::Vector2d lo(1e18, 1e18), hi(-1e18, -1e18);
  for (const auto& p : map_points) {
    lo = lo.cwiseMin(p.cast<double>());
    hi = hi.cwiseMax(p.cast<double>());
  }
  const int pad = (1 << o.branch_and_bound_depth) + int(std::ceil(4 * o.blur_sigma_m / o.resolution_m));
  g.origin_m = lo - Eigen::Vector2d::Constant(pad * o.resolution_m);
  g.width = int((hi.x() - lo.x()) / o.resolution_m) + 2 * pad + 1;
  g.height = int((hi.y() - lo.y()) / o.resolution_m) + 2 * pad + 1;
  std::vector<float> L(size_t(g.width) * g.height, 0.f);
  const int k = int(std::ceil(3 * o.blur_sigma_m / o.resolution_m));
  const double inv2s2 = 1.0 / (2 * o.blur_sigma_m * o.blur_sigma_m);
  for (const auto& p : map_points) {
    const Eigen::Vector2d c = (p.cast<double>() - g.origin_m) / o.resolution_m;
    const int cx = int(c.x()), cy = int(c.y());
    for (int dy = -k; dy <= k; ++dy) {
      for (int dx = -k; dx <= k; ++dx) {
        const double ex = (cx + dx + 0.5 - c.x()) * o.resolution_m, ey = (cy + dy + 0.5 - c.y()) * o.resolution_m;
        float& cell = L[size_t(cy + dy) * g.width + cx + dx];
        cell = std::max(cell, float(std::exp(-(ex * ex + ey * ey) * inv2s2)));
      }
    }
  }
  g.pooled.push_back(std::move(L));
  for (int h = 1; h < o.branch_and_bound_depth; ++h) {
    const int half = 1 << (h - 1);
    const std::vector<float>& prev = g.pooled.back();
    std::vector<float> next(prev.size(), 0.f);
    auto get = [&](int x, int y) { return x < g.width && y < g.height ? prev[size_t(y) * g.width + x] : 0.f; };
    for (int y = 0; y < g.height; ++y) {
      for (int x = 0; x < g.width; ++x) {
        next[size_t(y) * g.width + x] =
            std::max(std::max(get(x, y), get(x + half, y)), std::max(get(x, y + half), get(x + half, y + half)));
      }
    }
    g.pooled.push_back(std::move(next));
  }
  return g;
}

struct Candidate {
  int rotation = 0, x = 0, y = 0;  ///< rotation index, cell offsets
  float score = 0.f;
};

struct Search {
  const PrecomputedGrids* grids;
  std::vector<std::vector<Eigen::Vector2i>> cells;  ///< discretised query per rotation
  std::vector<double> yaw_rad;
  Candidate best;
  int scored = 0;

  float score(const Candidate& c, int h) {
    ++scored;
    double sum = 0;
    for (const Eigen::Vector2i& p : cells[size_t(c.rotation)]) sum += grids->at(h, p.x() + c.x, p.y() + c.y);
    return float(sum / cells[size_t(c.rotation)].size());
  }
  /// Depth-first branch and bound: children of a height-h candidate cover its 2^h x 2^h offsets.
  void branch(std::vector<Candidate> level, int h) {
    for (Candidate& c : level) c.score = score(c, h);
    std::sort(level.begin(), level.end(), [](const Candidate& a, const Candidate& b) { return a.score > b.score; });
    for (const Candidate& c : level) {
      if (c.score <= best.score) break;
      if (h == 0) {
        best = c;
        continue;
      }
      const int half = 1 << (h - 1);
      std::vector<Candidate> children;
      for (int dx : {0, half}) {
        for (int dy : {0, half}) children.push_back({c.rotation, c.x + dx, c.y + dy, 0.f});
      }
      branch(std::move(children), h - 1);
    }
  }
};

/// Point-to-point ICP refinement (Gauss-Newton on x, y, yaw) with a hashed-grid nearest neighbour.
void refine(const std::vector<Eigen::Vector2f>& map_points, const std::vector<Eigen::Vector2f>& query,
            const LoopVerifierOptions& o, LoopVerification* v) {
  const double cell = 0.3;
  auto key = [&](double x, double y) {
    // Shifted as unsigned: a left shift of a negative value is undefined behaviour.
    return int64_t((uint64_t(int64_t(std::floor(x / cell))) << 32) ^ uint32_t(int32_t(std::floor(y / cell))));
  };
  std::unordered_map<int64_t, std::vector<Eigen::Vector2d>> hash;
  for (const auto& p : map_points) hash[key(p.x(), p.y())].push_back(p.cast<double>());
  // Calls f(m, squared distance) for every map point m in the 3 x 3 hash cells around p.
  const auto for_each_near = [&](const Eigen::Vector2d& p, const auto& f) {
    for (int dx = -1; dx <= 1; ++dx) {
      for (int dy = -1; dy <= 1; ++dy) {
        auto cell_points = hash.find(key(p.x() + dx * cell, p.y() + dy * cell));
        if (cell_points == hash.end()) continue;
        for (const auto& m : cell_points->second) f(m, (m - p).squaredNorm());
      }
    }
  };
  SE2 T = v->T_map_query;
  Eigen::Matrix3d H = Eigen::Matrix3d::Identity();
  double sq_sum = 0;
  int inliers = 0;
  for (int it = 0; it < o.icp_iterations; ++it) {
    const double gate = it < 3 ? 2 * cell : o.icp_inlier_distance_m;
    H.setZero();
    Eigen::Vector3d b = Eigen::Vector3d::Zero();
    sq_sum = 0;
    inliers = 0;
    const Eigen::Matrix2d R = T.rotation();
    for (const auto& qf : query) {
      const Eigen::Vector2d q = qf.cast<double>(), p = T * q;
      double best = gate * gate;
      Eigen::Vector2d nn;
      for_each_near(p, [&](const Eigen::Vector2d& m, double d2) {
        if (d2 < best) best = d2, nn = m;
      });
      if (best >= gate * gate) continue;
      const Eigen::Vector2d e = p - nn;
      Eigen::Matrix<double, 2, 3> J;
      J << 1, 0, -(R * q).y(), 0, 1, (R * q).x();
      H += J.transpose() * J;
      b += J.transpose() * e;
      sq_sum += e.squaredNorm();
      ++inliers;
    }
    if (inliers < 3) break;
    const Eigen::Vector3d dx = -H.ldlt().solve(b);
    if (!dx.allFinite()) break;
    T = SE2(T.translation() + dx.head<2>(), T.yaw() + dx.z());
    if (dx.norm() < 1e-6) break;
  }
  v->T_map_query = T;
  v->inlier_fraction = query.empty() ? 0.0 : double(inliers) / query.size();
  // Covariance from point-to-line residuals at the result (the map's local line through each
  // nearest point, from its neighbours within one hash cell): a point-to-point Hessian is
  // isotropic in translation whatever the geometry, so a match in a featureless corridor, free to
  // slide along it, got centimetres along it too (MIT CSAIL split: five closures of one robot's
  // return to its start corridor 0.6-3.3 m off along it, all accepted with tight covariances).
  // Directions no line constrains get the search window as their spread.
  Eigen::Matrix3d Hl = Eigen::Matrix3d::Zero();
  double line_sq = 0;
  int lines = 0;
  const Eigen::Matrix2d R = T.rotation();
  for (const auto& qf : query) {
    const Eigen::Vector2d q = qf.cast<double>(), p = T * q;
    double best = o.icp_inlier_distance_m * o.icp_inlier_distance_m;
    Eigen::Vector2d nn;
    Eigen::Matrix2d scatter = Eigen::Matrix2d::Zero();
    Eigen::Vector2d sum = Eigen::Vector2d::Zero();
    int near = 0;
    for_each_near(p, [&](const Eigen::Vector2d& m, double d2) {
      if (d2 < best) best = d2, nn = m;
      if (d2 < cell * cell) sum += m, scatter += m * m.transpose(), ++near;
    });
    if (best >= o.icp_inlier_distance_m * o.icp_inlier_distance_m || near < 3) continue;
    const Eigen::Vector2d mean = sum / near;
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> eig(scatter / near - mean * mean.transpose());
    if (eig.eigenvalues()(0) > 0.25 * eig.eigenvalues()(1)) continue;  // no line here (a corner, a blob)
    const Eigen::Vector2d normal = eig.eigenvectors().col(0);
    Eigen::Matrix<double, 1, 3> J;
    J << normal.x(), normal.y(), normal.dot(Eigen::Vector2d(-(R * q).y(), (R * q).x()));
    Hl += J.transpose() * J;
    const double r = normal.dot(p - nn);
    line_sq += r * r;
    ++lines;
  }
  const double sigma2 = std::max(lines > 3 ? line_sq / (lines - 3.0) : 1.0, 1e-4);
  const Eigen::Vector3d prior(1.0 / (o.linear_window_m * o.linear_window_m),
                              1.0 / (o.linear_window_m * o.linear_window_m),
                              1.0 / (o.angular_window_rad * o.angular_window_rad));
  Eigen::Matrix3d cov = (Hl / sigma2 + Eigen::Matrix3d(prior.asDiagonal())).inverse();
  if (!cov.allFinite()) cov = Eigen::Matrix3d::Identity();
  cov(0, 0) += o.min_covariance_sigma_m * o.min_covariance_sigma_m;
  cov(1, 1) += o.min_covariance_sigma_m * o.min_covariance_sigma_m;
  cov(2, 2) += o.min_covariance_sigma_rad * o.min_covariance_sigma_rad;
  v->covariance = cov;
}

}  // namespace

LoopVerification verify_loop(const std::vector<Eigen::Vector2f>& map_points, const std::vector<Eigen::Vector2f>& query,
                             const SE2& initial, const LoopVerifierOptions& o) {
  LoopVerification v;
  if (int(map_points.size()) < o.min_points || int(query.size()) < o.min_points) {
    v.reason = "too few points";
    return v;
  }
  const PrecomputedGrids grids = build_grids(map_points, o);
  Search search{&grids, {}, {}, {}, 0};
  double max_range = 0;
  for (const auto& p : query) max_range = std::max(max_range, double(p.norm()));
  max_range = std::min(max_range, o.max_range_for_step_m);
  const double step = std::acos(1.0 - o.resolution_m * o.resolution_m / (2.0 * max_range * max_range));
  const int n_rot = int(std::ceil(o.angular_window_rad / step));
  const int top = o.branch_and_bound_depth - 1, w = 1 << top;
  const int window_cells = int(std::ceil(o.linear_window_m / o.resolution_m));
  std::vector<Candidate> level;
  for (int r = -n_rot; r <= n_rot; ++r) {
    const double yaw = initial.yaw() + r * step;
    if (std::abs(r * step) > M_PI && r > 0) break;
    const SE2 T(initial.translation(), yaw);
    std::vector<Eigen::Vector2i> cells;
    for (const auto& p : query) {
      const Eigen::Vector2d c = (T * p.cast<double>() - grids.origin_m) / o.resolution_m;
      cells.emplace_back(int(std::floor(c.x())), int(std::floor(c.y())));
    }
    search.cells.push_back(std::move(cells));
    search.yaw_rad.push_back(yaw);
    for (int x = -window_cells; x <= window_cells; x += w) {
      for (int y = -window_cells; y <= window_cells; y += w) level.push_back({int(search.cells.size()) - 1, x, y, 0.f});
    }
  }
  search.best.score = float(o.min_score);
  search.branch(std::move(level), top);
  v.candidates_scored = search.scored;
  if (search.best.score <= float(o.min_score)) {
    v.reason = "no candidate above min_score";
    return v;
  }
  v.score = search.best.score;
  v.T_map_query = SE2(initial.translation() + Eigen::Vector2d(search.best.x, search.best.y) * o.resolution_m,
                      search.yaw_rad[size_t(search.best.rotation)]);
  refine(map_points, query, o, &v);
  if (v.inlier_fraction < o.min_inlier_fraction) {
    v.reason = "inlier fraction " + std::to_string(v.inlier_fraction) + " after ICP";
    return v;
  }
  v.accepted = true;
  return v;
}

}  // namespace cairn::base
