#include "common/trajectory.h"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <sstream>

#include "common/errors.h"

namespace cairn {

Trajectory read_trajectory_csv(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw InputError(path + ": cannot open trajectory file");
  Trajectory out;
  std::string line;
  int line_no = 0;
  while (std::getline(in, line)) {
    ++line_no;
    if (line.empty() || line[0] == '#' || line.rfind("stamp_ns", 0) == 0) continue;
    std::replace(line.begin(), line.end(), ',', ' ');
    std::istringstream ss(line);
    long long stamp = 0;
    double x, y, yaw;
    if (!(ss >> stamp >> x >> y >> yaw) || !std::isfinite(x) || !std::isfinite(y) || !std::isfinite(yaw)) {
      throw InputError(path + ":" + std::to_string(line_no) +
                       ": expected 'stamp_ns,x_m,y_m,yaw_rad' with finite numbers");
    }
    out.push_back({StampNs(stamp), SE2(x, y, yaw)});
  }
  std::stable_sort(out.begin(), out.end(), [](auto& a, auto& b) { return a.stamp_ns < b.stamp_ns; });
  return out;
}

bool write_trajectory_csv(const std::string& path, const Trajectory& trajectory) {
  std::ofstream out(path);
  if (!out) return false;
  out << "stamp_ns,x_m,y_m,yaw_rad\n";
  out.precision(9);
  for (const auto& p : trajectory) {
    out << p.stamp_ns << ',' << p.pose.x() << ',' << p.pose.y() << ',' << p.pose.yaw() << '\n';
  }
  return bool(out);
}

std::optional<SE2> interpolate_pose(const Trajectory& t, StampNs stamp_ns, StampNs max_gap_ns) {
  if (t.empty() || stamp_ns < t.front().stamp_ns || stamp_ns > t.back().stamp_ns) return std::nullopt;
  auto it =
      std::lower_bound(t.begin(), t.end(), stamp_ns, [](const StampedPose& p, StampNs s) { return p.stamp_ns < s; });
  if (it->stamp_ns == stamp_ns) return it->pose;
  const StampedPose& b = *it;
  const StampedPose& a = *(it - 1);
  if (b.stamp_ns - a.stamp_ns > max_gap_ns) return std::nullopt;
  const double s = double(stamp_ns - a.stamp_ns) / double(b.stamp_ns - a.stamp_ns);
  return SE2::interpolate(a.pose, b.pose, s);
}

SE2 align_points_2d(const std::vector<Eigen::Vector2d>& est, const std::vector<Eigen::Vector2d>& ref) {
  const size_t n = std::min(est.size(), ref.size());
  if (n == 0) return SE2();
  Eigen::Vector2d me = Eigen::Vector2d::Zero(), mr = Eigen::Vector2d::Zero();
  for (size_t i = 0; i < n; ++i) {
    me += est[i];
    mr += ref[i];
  }
  me /= double(n);
  mr /= double(n);
  double sxx = 0, sxy = 0;  // sum of dot and cross products of centred pairs
  for (size_t i = 0; i < n; ++i) {
    const Eigen::Vector2d a = est[i] - me, b = ref[i] - mr;
    sxx += a.dot(b);
    sxy += a.x() * b.y() - a.y() * b.x();
  }
  const double yaw = std::atan2(sxy, sxx);
  const Eigen::Vector2d t = mr - Eigen::Rotation2Dd(yaw) * me;
  return SE2(t, yaw);
}

std::optional<TrajectoryErrorStats> trajectory_error(const Trajectory& estimate, const Trajectory& reference,
                                                     const TrajectoryErrorOptions& options) {
  std::vector<SE2> est, ref;
  for (const auto& p : estimate) {
    if (auto r = interpolate_pose(reference, p.stamp_ns, options.max_gap_ns)) {
      est.push_back(p.pose);
      ref.push_back(*r);
    }
  }
  if (est.size() < 2) return std::nullopt;
  TrajectoryErrorStats s;
  s.matched = int(est.size());
  if (options.align) {
    std::vector<Eigen::Vector2d> pe, pr;
    for (size_t i = 0; i < est.size(); ++i) {
      pe.push_back(est[i].translation());
      pr.push_back(ref[i].translation());
    }
    s.T_reference_estimate = align_points_2d(pe, pr);
  }
  double sq = 0, sum = 0;
  for (size_t i = 0; i < est.size(); ++i) {
    const double e = ((s.T_reference_estimate * est[i]).translation() - ref[i].translation()).norm();
    sq += e * e;
    sum += e;
    s.ate_max_m = std::max(s.ate_max_m, e);
  }
  s.ate_rmse_m = std::sqrt(sq / est.size());
  s.ate_mean_m = sum / est.size();
  for (size_t i = 1; i < est.size(); ++i) {
    const SE2 d = est[i - 1].between(est[i]).inverse() * ref[i - 1].between(ref[i]);
    s.rpe_trans_mean_m += d.translation().norm();
    s.rpe_rot_mean_rad += std::abs(d.yaw());
  }
  s.rpe_trans_mean_m /= double(est.size() - 1);
  s.rpe_rot_mean_rad /= double(est.size() - 1);
  return s;
}

}  // namespace cairn
