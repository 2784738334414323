#include "common/registration/rgb_icp.h"

#include <Eigen/Dense>
#include <algorithm>
#include <array>
#include <cmath>
#include <random>
#include <tuple>

#include "common/registration/knn_index.h"
#include "common/registration/point_features.h"

namespace cairn::registration {
namespace {

using Matches = std::vector<std::pair<int, int>>;

Eigen::Vector3d xyz(const ColoredPoint& p) { return Eigen::Vector3d(p.x, p.y, p.z); }

double colour_distance(const ColoredPoint& a, const ColoredPoint& b) {
  return std::sqrt(std::pow(a.r - b.r, 2) + std::pow(a.g - b.g, 2) + std::pow(a.b - b.b, 2));
}

/// Rows of xyz plus colour scaled to metres, for closest points in the joint space.
std::vector<float> joint_rows(const ColoredCloud& c, const Eigen::Isometry3d& T, float colour_scale) {
  std::vector<float> rows;
  rows.reserve(c.size() * 6);
  for (const ColoredPoint& p : c) {
    const Eigen::Vector3d q = T * xyz(p);
    rows.insert(rows.end(),
                {float(q.x()), float(q.y()), float(q.z()), colour_scale * p.r, colour_scale * p.g, colour_scale * p.b});
  }
  return rows;
}

std::vector<float> xyz_rows_transformed(const ColoredCloud& c, const Eigen::Isometry3d& T) {
  std::vector<float> rows;
  rows.reserve(c.size() * 3);
  for (const ColoredPoint& p : c) {
    const Eigen::Vector3d q = T * xyz(p);
    rows.insert(rows.end(), {float(q.x()), float(q.y()), float(q.z())});
  }
  return rows;
}

Eigen::Isometry3d umeyama_fit(const ColoredCloud& src, const ColoredCloud& tgt, const Matches& m,
                              const std::vector<int>& set) {
  Eigen::Matrix3Xd a(3, set.size()), b(3, set.size());
  for (size_t k = 0; k < set.size(); ++k) {
    a.col(Eigen::Index(k)) = xyz(src[size_t(m[size_t(set[k])].first)]);
    b.col(Eigen::Index(k)) = xyz(tgt[size_t(m[size_t(set[k])].second)]);
  }
  Eigen::Isometry3d T;
  T.matrix() = Eigen::umeyama(a, b, false);
  return T;
}

std::vector<int> inlier_set(const ColoredCloud& src, const ColoredCloud& tgt, const Matches& m,
                            const Eigen::Isometry3d& T, double inlier_m) {
  std::vector<int> set;
  const double gate2 = inlier_m * inlier_m;
  for (size_t k = 0; k < m.size(); ++k)
    if ((T * xyz(src[size_t(m[k].first)]) - xyz(tgt[size_t(m[k].second)])).squaredNorm() < gate2) set.push_back(int(k));
  return set;
}

/// Edge-length pre-check (Open3D's CorrespondenceCheckerBasedOnEdgeLength): a rigid motion keeps
/// the sampled triangle's edges; samples that do not are rejected before any model is fitted.
bool edges_agree(const ColoredCloud& src, const ColoredCloud& tgt, const Matches& m, const std::array<int, 3>& s,
                 double similarity) {
  for (int a = 0; a < 3; ++a) {
    const int b = (a + 1) % 3;
    const double ls = (xyz(src[size_t(m[size_t(s[a])].first)]) - xyz(src[size_t(m[size_t(s[b])].first)])).norm();
    const double lt = (xyz(tgt[size_t(m[size_t(s[a])].second)]) - xyz(tgt[size_t(m[size_t(s[b])].second)])).norm();
    if (ls < 1e-6 || lt < 1e-6 || std::min(ls, lt) < similarity * std::max(ls, lt)) return false;
  }
  return true;
}

// RANSAC over the matches: 3 random pairs -> edge check -> Umeyama -> inliers; adaptive stop;
// refit on the best set.
Eigen::Isometry3d ransac(const ColoredCloud& src, const ColoredCloud& tgt, const Matches& m, const RgbIcpOptions& o,
                         int* inliers, int* iterations) {
  *inliers = 0;
  *iterations = 0;
  if (m.size() < 3) return Eigen::Isometry3d::Identity();
  std::mt19937 rng(o.seed);
  std::uniform_int_distribution<int> pick(0, int(m.size()) - 1);
  std::vector<int> best_set;
  double needed = o.ransac_iterations;
  int it = 0;
  for (; it < o.ransac_iterations && it < needed; ++it) {
    const std::array<int, 3> s{pick(rng), pick(rng), pick(rng)};
    if (s[0] == s[1] || s[1] == s[2] || s[0] == s[2]) continue;
    if (!edges_agree(src, tgt, m, s, o.ransac_edge_similarity)) continue;
    std::vector<int> set = inlier_set(src, tgt, m, umeyama_fit(src, tgt, m, {s[0], s[1], s[2]}), o.ransac_inlier_m);
    if (set.size() <= best_set.size()) continue;
    best_set = std::move(set);
    const double w = double(best_set.size()) / double(m.size());
    const double miss = 1.0 - w * w * w;
    if (miss <= 0.0) break;
    needed = std::log(1.0 - o.ransac_confidence) / std::log(miss);
  }
  *iterations = it;
  if (best_set.size() < 3) return Eigen::Isometry3d::Identity();
  const Eigen::Isometry3d best = umeyama_fit(src, tgt, m, best_set);
  *inliers = int(inlier_set(src, tgt, m, best, o.ransac_inlier_m).size());
  return best;
}

struct Overlap {
  double fitness = 0.0, rmse_m = 0.0;
};

Overlap overlap(const ColoredCloud& src, const KnnIndex& tgt_xyz, const Eigen::Isometry3d& T, double max_d) {
  std::vector<int> idx;
  std::vector<float> d2;
  tgt_xyz.knn(xyz_rows_transformed(src, T), 1, &idx, &d2);
  int n = 0;
  double sq = 0.0;
  for (float d : d2)
    if (d <= max_d * max_d) ++n, sq += d;
  Overlap ov;
  ov.fitness = src.empty() ? 0.0 : double(n) / double(src.size());
  ov.rmse_m = n ? std::sqrt(sq / n) : 0.0;
  return ov;
}

struct IcpState {
  Eigen::Isometry3d T;
  bool done = false, degenerate = false;  ///< degenerate: some step was in an unobservable direction
  int iterations = 0;
};

// Point-to-plane ICP with joint xyz+colour closest points (one batched query per iteration).
void icp(const ColoredCloud& src, const ColoredCloud& tgt, const std::vector<Eigen::Vector3f>& tn,
         const KnnIndex& joint, const RgbIcpOptions& o, IcpState* st) {
  std::vector<int> idx;
  std::vector<float> d2;
  const double gate2 = o.max_correspondence_m * o.max_correspondence_m;
  Eigen::Vector3d c = Eigen::Vector3d::Zero();  // rotations about the cloud's centre: well conditioned
  for (const ColoredPoint& p : src) c += xyz(p) / double(src.size());
  for (; st->iterations < o.max_iterations && !st->done; ++st->iterations) {
    joint.knn(joint_rows(src, st->T, float(o.colour_scale_m)), 1, &idx, &d2);
    Eigen::Matrix<double, 6, 6> A = Eigen::Matrix<double, 6, 6>::Zero();
    Eigen::Matrix<double, 6, 1> b = Eigen::Matrix<double, 6, 1>::Zero();
    int used = 0;
    for (size_t i = 0; i < src.size(); ++i) {
      if (idx[i] < 0) continue;
      const ColoredPoint& t = tgt[size_t(idx[i])];
      const Eigen::Vector3d s = st->T * xyz(src[i]), tp = xyz(t);
      const Eigen::Vector3d n = tn[size_t(idx[i])].cast<double>();
      if ((s - tp).squaredNorm() > gate2 || !n.allFinite()) continue;
      const double dc = colour_distance(src[i], t);
      const double w = 1.0 / (1.0 + std::pow(dc / 60.0, 2));
      Eigen::Matrix<double, 6, 1> J;
      J << (s - st->T * c).cross(n), n;
      const double r = n.dot(s - tp);
      A.selfadjointView<Eigen::Lower>().rankUpdate(J, w);
      b -= w * J * r;
      ++used;
    }
    if (used < o.min_points) break;
    A = A.selfadjointView<Eigen::Lower>();
    // Solve in the observable subspace: directions with a near-zero eigenvalue (sliding on a plane,
    // turning about a cylinder's axis) get no step; the registration is then flagged degenerate.
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix<double, 6, 6>> eig(A);
    const double floor = o.min_eigen_ratio * std::max(1e-12, eig.eigenvalues()(5));
    Eigen::Matrix<double, 6, 1> x = Eigen::Matrix<double, 6, 1>::Zero();
    for (int k = 0; k < 6; ++k) {
      if (eig.eigenvalues()(k) < floor) {
        st->degenerate = true;
        continue;
      }
      x += eig.eigenvectors().col(k) * (eig.eigenvectors().col(k).dot(b) / eig.eigenvalues()(k));
    }
    if (!x.allFinite()) break;
    Eigen::Isometry3d dR = Eigen::Isometry3d::Identity();
    const double angle = x.head<3>().norm();
    if (angle > 0) dR.linear() = Eigen::AngleAxisd(angle, x.head<3>() / angle).toRotationMatrix();
    const Eigen::Vector3d centre = st->T * c;
    const Eigen::Isometry3d dT = Eigen::Translation3d(centre + x.tail<3>()) * dR * Eigen::Translation3d(-centre);
    st->T = dT * st->T;
    st->done = x.tail<3>().norm() < o.delta_translation_m && angle < o.delta_rotation_rad;
  }
}

/// Algorithm 3 steps 1-2: features + RANSAC; returns the seed for ICP (T_prior unless RANSAC
/// has >= r inliers and overlaps better).
Eigen::Isometry3d feature_seed(const ColoredCloud& src, const ColoredCloud& tgt, const Eigen::Isometry3d& T_prior,
                               const RgbIcpOptions& o, RgbIcpResult* r) {
  const bool coarse = o.feature_voxel_m > o.voxel_m;
  const ColoredCloud fs = coarse ? voxel_grid(src, o.feature_voxel_m) : src;
  const ColoredCloud ft = coarse ? voxel_grid(tgt, o.feature_voxel_m) : tgt;
  const KnnIndex is(xyz_rows(fs), 3), it(xyz_rows(ft), 3);
  const auto ns = estimate_normals(fs, is, o.normal_neighbours), nt = estimate_normals(ft, it, o.normal_neighbours);
  const Matches matches = match_features(fs, compute_fpfh(fs, ns, is, o.feature_radius_m), ft,
                                         compute_fpfh(ft, nt, it, o.feature_radius_m), o.max_feature_colour_diff);
  r->feature_matches = int(matches.size());
  const Eigen::Isometry3d T_ransac = ransac(fs, ft, matches, o, &r->feature_inliers, &r->ransac_iterations);
  if (r->feature_inliers < o.min_inliers) return T_prior;
  const double gate = std::max(o.ransac_inlier_m, coarse ? o.feature_voxel_m : 0.0);
  if (overlap(fs, it, T_ransac, gate).fitness <= overlap(fs, it, T_prior, gate).fitness) return T_prior;
  r->used_prior = false;
  return T_ransac;
}

}  // namespace

ColoredCloud voxel_grid(const ColoredCloud& cloud, double voxel_m) {
  using Key = std::tuple<int64_t, int64_t, int64_t>;
  std::vector<std::pair<Key, size_t>> keyed;
  keyed.reserve(cloud.size());
  for (size_t i = 0; i < cloud.size(); ++i) {
    const ColoredPoint& p = cloud[i];
    if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z)) continue;
    if (voxel_m <= 0.0) {
      keyed.push_back({Key{int64_t(i), 0, 0}, i});
      continue;
    }
    keyed.push_back({Key{int64_t(std::floor(p.x / voxel_m)), int64_t(std::floor(p.y / voxel_m)),
                         int64_t(std::floor(p.z / voxel_m))},
                     i});
  }
  std::sort(keyed.begin(), keyed.end());
  ColoredCloud out;
  for (size_t a = 0; a < keyed.size();) {
    size_t b = a;
    double s[6] = {0, 0, 0, 0, 0, 0};
    for (; b < keyed.size() && std::get<0>(keyed[b]) == std::get<0>(keyed[a]); ++b) {
      const ColoredPoint& p = cloud[keyed[b].second];
      s[0] += p.x, s[1] += p.y, s[2] += p.z, s[3] += p.r, s[4] += p.g, s[5] += p.b;
    }
    const double n = double(b - a);
    out.push_back(ColoredPoint{float(s[0] / n), float(s[1] / n), float(s[2] / n), uint8_t(std::lround(s[3] / n)),
                               uint8_t(std::lround(s[4] / n)), uint8_t(std::lround(s[5] / n))});
    a = b;
  }
  return out;
}

RgbIcpResult rgb_icp(const ColoredCloud& source, const ColoredCloud& target, const Eigen::Isometry3d& T_prior,
                     const RgbIcpOptions& o) {
  RgbIcpResult r;
  r.T_target_source = T_prior;
  if (!T_prior.matrix().allFinite()) return r.reason = "non-finite prior", r;
  const ColoredCloud src = voxel_grid(source, o.voxel_m), tgt = voxel_grid(target, o.voxel_m);
  if (int(src.size()) < o.min_points || int(tgt.size()) < o.min_points) {
    r.reason = src.empty() || tgt.empty() ? "empty cloud" : "too few points to register";
    return r;
  }
  const KnnIndex tgt_xyz(xyz_rows(tgt), 3);
  const std::vector<Eigen::Vector3f> tn = estimate_normals(tgt, tgt_xyz, o.normal_neighbours);
  IcpState st;
  st.T = o.use_features ? feature_seed(src, tgt, T_prior, o, &r) : T_prior;
  const KnnIndex joint(joint_rows(tgt, Eigen::Isometry3d::Identity(), float(o.colour_scale_m)), 6);
  icp(src, tgt, tn, joint, o, &st);
  r.iterations = st.iterations;
  r.T_target_source = st.T;
  const Overlap ov = overlap(src, tgt_xyz, st.T, o.max_correspondence_m);
  r.score = ov.fitness;
  r.rmse_m = ov.rmse_m;
  r.degenerate = st.degenerate;
  r.converged = st.done && ov.fitness > 0.0 && !st.degenerate;
  if (st.degenerate)
    r.reason = "degenerate registration: geometry constrains only some of the 6 DoF";
  else if (!st.done)
    r.reason = st.iterations < o.max_iterations ? "too few correspondences within max_correspondence_m"
                                                : "ICP did not converge within max_iterations";
  else if (ov.fitness <= 0.0)
    r.reason = "no overlap after alignment";
  return r;
}

}  // namespace cairn::registration
