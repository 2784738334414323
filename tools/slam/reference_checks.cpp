#include "tools/slam/reference_checks.h"

#include <Eigen/SVD>
#include <algorithm>
#include <cmath>
#include <string>

#include "common/errors.h"
#include "common/registration/knn_index.h"

namespace cairn::slam {
namespace {

double median(std::vector<double> v) {
  if (v.empty()) return 0.0;
  const size_t mid = v.size() / 2;
  std::nth_element(v.begin(), v.begin() + long(mid), v.end());
  return v[mid];
}

void check_lengths(size_t scans, size_t poses, const char* what) {
  if (scans != poses) {
    throw InputError(std::string(what) + ": " + std::to_string(scans) + " scans but " + std::to_string(poses) +
                     " poses");
  }
}

}  // namespace

RevisitConsistency revisit_consistency(const std::vector<LaserScan>& scans, const std::vector<SE2>& T_world_base,
                                       const RevisitConsistencyOptions& o) {
  check_lengths(scans.size(), T_world_base.size(), "revisit consistency");
  std::vector<float> xy;  // world endpoints, row-major
  std::vector<int> scan_of;
  for (size_t i = 0; i < scans.size(); ++i) {
    const Eigen::Matrix2d R = T_world_base[i].rotation();
    for (const Eigen::Vector2f& p : scan_to_points(scans[i])) {
      if (p.norm() > o.max_range_m) continue;
      const Eigen::Vector2d w = R * p.cast<double>() + T_world_base[i].translation();
      xy.push_back(float(w.x()));
      xy.push_back(float(w.y()));
      scan_of.push_back(int(i));
    }
  }
  RevisitConsistency out;
  out.points = int(scan_of.size());
  const int gap = std::max(1, o.min_index_gap);
  std::vector<double> nn;
  // The scans are queried in blocks of `gap`; each block against an index of every endpoint at least
  // `gap` scans before the block or after its end (one kd-tree per block, not per scan).
  for (int b0 = 0; b0 < int(scans.size()); b0 += gap) {
    std::vector<float> others, queries;
    for (size_t k = 0; k < scan_of.size(); ++k) {
      const int s = scan_of[k];
      const bool in_block = s >= b0 && s < b0 + gap, same_pass = s >= b0 - gap && s < b0 + 2 * gap;
      if (!in_block && same_pass) continue;
      std::vector<float>& into = in_block ? queries : others;
      into.push_back(xy[2 * k]);
      into.push_back(xy[2 * k + 1]);
    }
    if (others.empty() || queries.empty()) continue;
    const registration::KnnIndex index(std::move(others), 2);
    std::vector<int> idx;
    std::vector<float> d2;
    index.knn(queries, 1, &idx, &d2);
    for (size_t q = 0; q < idx.size(); ++q) {
      if (idx[q] >= 0 && d2[q] <= o.radius_m * o.radius_m) nn.push_back(std::sqrt(double(d2[q])));
    }
  }
  if (out.points == 0 || nn.empty()) return out;
  out.revisit_fraction = double(nn.size()) / out.points;
  double sum = 0.0;
  int close = 0;
  for (double d : nn) {
    sum += d;
    close += d < o.close_m;
  }
  out.mean_nn_m = sum / double(nn.size());
  out.within_close_fraction = double(close) / double(nn.size());
  out.median_nn_m = median(nn);
  return out;
}

ForwardRange forward_range(const std::vector<LaserScan>& scans, const std::vector<std::vector<SE2>>& trajectories,
                           const ForwardRangeOptions& o) {
  for (const auto& t : trajectories) check_lengths(scans.size(), t.size(), "forward range");
  ForwardRange out;
  const size_t n_traj = trajectories.size();
  out.trajectory_forward_m.assign(n_traj, 0.0);
  std::vector<std::vector<double>> differences(n_traj);
  // The range straight ahead, if the beams within half_width of it agree (a flat surface ahead).
  const auto ahead = [&](const LaserScan& s, double* range_m) {
    if (s.angle_increment_rad <= 0.f) return false;
    const long centre = std::lround(-s.angle_min_rad / s.angle_increment_rad);
    std::vector<double> r;
    for (long i = centre - o.half_width_beams; i <= centre + o.half_width_beams; ++i) {
      if (i < 0 || i >= long(s.ranges_m.size())) return false;
      const float v = s.ranges_m[size_t(i)];
      if (!std::isfinite(v) || v < o.min_range_m || v > o.max_range_m) return false;
      r.push_back(v);
    }
    const auto [lo, hi] = std::minmax_element(r.begin(), r.end());
    *range_m = s.ranges_m[size_t(centre)];
    return *hi - *lo <= o.flatness_fraction * *range_m;
  };
  for (size_t i = 0; i + 1 < scans.size(); ++i) {
    double r0 = 0.0, r1 = 0.0;
    if (!ahead(scans[i], &r0) || !ahead(scans[i + 1], &r1)) continue;
    const double laser_m = r0 - r1;
    if (laser_m < o.min_motion_m) continue;
    std::vector<double> forward(n_traj);
    bool ok = true;
    for (size_t t = 0; t < n_traj && ok; ++t) {
      const SE2 step = trajectories[t][i].between(trajectories[t][i + 1]);
      forward[t] = step.x();
      ok = std::abs(step.yaw()) <= o.max_turn_rad && std::abs(forward[t] - laser_m) <= o.max_disagreement_m;
    }
    if (!ok) continue;
    ++out.pairs;
    out.laser_forward_m += laser_m;
    for (size_t t = 0; t < n_traj; ++t) {
      out.trajectory_forward_m[t] += forward[t];
      differences[t].push_back(forward[t] - laser_m);
    }
  }
  for (size_t t = 0; t < n_traj; ++t) {
    out.ratio.push_back(out.laser_forward_m > 0.0 ? out.trajectory_forward_m[t] / out.laser_forward_m : 0.0);
    out.median_difference_m.push_back(median(differences[t]));
  }
  return out;
}

AffineFit affine_fit(const std::vector<Eigen::Vector2d>& est, const std::vector<Eigen::Vector2d>& ref) {
  if (est.size() != ref.size() || est.size() < 3) {
    throw InputError("affine fit: needs >= 3 matched positions, got " + std::to_string(est.size()) + " and " +
                     std::to_string(ref.size()));
  }
  Eigen::MatrixXd X(est.size(), 3), Y(ref.size(), 2);
  for (size_t i = 0; i < est.size(); ++i) {
    X.row(long(i)) << est[i].x(), est[i].y(), 1.0;
    Y.row(long(i)) = ref[i].transpose();
  }
  const Eigen::MatrixXd P = X.colPivHouseholderQr().solve(Y);  // 3 x 2: [A^T; b^T]
  const Eigen::MatrixXd residual = X * P - Y;
  AffineFit out;
  out.rmse_m = std::sqrt(residual.rowwise().squaredNorm().mean());
  const Eigen::Matrix2d A = P.topRows<2>().transpose();
  const Eigen::JacobiSVD<Eigen::Matrix2d> svd(A, Eigen::ComputeFullU);
  out.scale_major = svd.singularValues()(0);
  out.scale_minor = svd.singularValues()(1);
  const Eigen::Vector2d axis = svd.matrixU().col(0);
  out.major_axis_deg = std::fmod(std::atan2(axis.y(), axis.x()) * 180.0 / M_PI + 180.0, 180.0);
  return out;
}

ScanChecks scan_checks(const CarmenLog& corrected, const Trajectory& reference, const std::vector<size_t>& scan_index,
                       const Trajectory& estimate, const RevisitConsistencyOptions& consistency,
                       const ForwardRangeOptions& forward) {
  check_lengths(scan_index.size(), reference.size(), "scan checks (reference)");
  std::vector<LaserScan> scans;
  std::vector<SE2> ref, est;
  std::vector<Eigen::Vector2d> ref_xy, est_xy;
  size_t j = 0;  // both sorted by stamp
  for (const StampedPose& e : estimate) {
    while (j < reference.size() && reference[j].stamp_ns < e.stamp_ns) ++j;
    if (j == reference.size() || reference[j].stamp_ns != e.stamp_ns) continue;
    if (scan_index[j] >= corrected.scans.size()) throw InputError("scan checks: scan index out of range");
    scans.push_back(corrected.scans[scan_index[j]].scan);
    ref.push_back(reference[j].pose);
    est.push_back(e.pose);
    ref_xy.push_back(reference[j].pose.translation());
    est_xy.push_back(e.pose.translation());
  }
  ScanChecks out;
  out.poses = int(scans.size());
  out.reference = revisit_consistency(scans, ref, consistency);
  out.estimate = revisit_consistency(scans, est, consistency);
  out.forward = forward_range(scans, {ref, est}, forward);
  out.affine = affine_fit(est_xy, ref_xy);
  return out;
}

}  // namespace cairn::slam
