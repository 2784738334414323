#include "base_station/core/landmarks.h"

#include <Eigen/Geometry>
#include <cmath>
#include <cstdio>

#include "common/robot_markers.h"

namespace cairn::base {
namespace {

double spread_of(const Eigen::Matrix2Xd& p) {
  double best = 0;
  for (int i = 0; i < p.cols(); ++i) {
    for (int j = i + 1; j < p.cols(); ++j) best = std::max(best, (p.col(i) - p.col(j)).norm());
  }
  return best;
}

}  // namespace

std::string format_number(const char* format, double value) {
  char buf[48];
  std::snprintf(buf, sizeof(buf), format, value);
  return buf;
}

std::string format_offset(const SE2& a, const SE2& b) {
  const SE2 E = a.between(b);
  return format_number("%.2f m", E.translation().norm()) + " and " +
         format_number("%.1f deg", std::abs(E.yaw()) * 180.0 / M_PI);
}

int accumulate_landmarks(const Keyframe& kf, double min_range_m, LocalLandmarks* landmarks, int* invalid) {
  int used = 0;
  for (const LandmarkObservation& o : kf.landmarks) {
    if (robot_of_marker(o.id)) continue;  // a teammate: it moves (sightings.h)
    if (!validate_landmark_observation(o).empty() || o.range_m < min_range_m) {
      if (invalid) ++*invalid;
      continue;
    }
    LocalLandmark& l = (*landmarks)[o.id];
    l.sum_m += kf.T_local_base * o.point_m();
    ++l.observations;
    if (o.range_m < l.nearest_range_m) {
      l.nearest_range_m = o.range_m;
      l.nearest = kf.id;
    }
    ++used;
  }
  return used;
}

int shared_landmarks(const LocalLandmarks& a, const LocalLandmarks& b) {
  int n = 0;
  for (const auto& [id, l] : a) n += b.count(id) > 0;
  return n;
}

LandmarkAlignment align_landmarks(const LocalLandmarks& a, const LocalLandmarks& b, int min_landmarks, double max_rms_m,
                                  double min_spread_m) {
  LandmarkAlignment out;
  for (const auto& [id, l] : a) {
    if (b.count(id)) out.used.push_back(id);
  }
  min_landmarks = std::max(min_landmarks, 2);
  while (true) {
    const int n = int(out.used.size());
    if (n < min_landmarks) {
      out.ok = false;
      out.reason = std::to_string(n) + " shared landmark(s) consistent (" + std::to_string(min_landmarks) + " needed)";
      if (!out.dropped.empty()) out.reason += ", " + std::to_string(out.dropped.size()) + " dropped as inconsistent";
      return out;
    }
    Eigen::Matrix2Xd pa(2, n), pb(2, n);
    for (int i = 0; i < n; ++i) {
      pa.col(i) = a.at(out.used[size_t(i)]).position_m();
      pb.col(i) = b.at(out.used[size_t(i)]).position_m();
    }
    const Eigen::Matrix3d T = Eigen::umeyama(pb, pa, false);  // maps b's points onto a's
    out.T_a_b = SE2(T(0, 2), T(1, 2), std::atan2(T(1, 0), T(0, 0)));
    Eigen::VectorXd err(n);
    for (int i = 0; i < n; ++i) err(i) = (out.T_a_b * Eigen::Vector2d(pb.col(i)) - pa.col(i)).norm();
    out.rms_m = std::sqrt(err.squaredNorm() / n);
    out.spread_m = spread_of(pa);
    if (out.rms_m <= max_rms_m) break;
    Eigen::Index worst = 0;
    err.maxCoeff(&worst);
    out.dropped.push_back(out.used[size_t(worst)]);
    out.used.erase(out.used.begin() + worst);
  }
  if (out.spread_m < min_spread_m) {
    out.reason = "shared landmarks span " + format_number("%.2f", out.spread_m) + " m (< " +
                 format_number("%.2f", min_spread_m) + " m): rotation too uncertain";
    return out;
  }
  out.ok = true;
  return out;
}

}  // namespace cairn::base
