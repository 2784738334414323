#pragma once
// Test helpers: featureless scans, and keyframes from a multi-robot log's robot (what the agent
// would send).
#include <cmath>
#include <limits>
#include <vector>

#include "common/keyframe.h"
#include "common/multirobot_log.h"

namespace cairn::base::testing {

/// A scan of a featureless field: every beam without a return (scans can never link robots).
inline LaserScan featureless_scan(StampNs stamp_ns) {
  LaserScan s;
  s.stamp_ns = stamp_ns;
  s.angle_min_rad = float(-M_PI);
  s.angle_increment_rad = float(M_PI / 90);
  s.range_max_m = 10.f;
  s.ranges_m.assign(180, std::numeric_limits<float>::infinity());
  return s;
}

/// Keyframes every `every` scans from the log's odometry; observations between keyframes are
/// re-expressed in the next keyframe's frame (what the agent does).
inline std::vector<Keyframe> keyframes_of(const RobotLogData& r, int every) {
  std::vector<Keyframe> out;
  size_t next_landmark = 0;
  for (size_t i = 0; i < r.scans.size(); i += size_t(every)) {
    Keyframe kf;
    kf.id = KeyframeId{r.robot, int32_t(out.size())};
    kf.stamp_ns = r.scans[i].stamp_ns;
    kf.T_local_base = r.odometry[i].T_odom_base;
    if (!out.empty()) kf.T_prev_this = out.back().T_local_base.between(kf.T_local_base);
    kf.edge_covariance = Covariance3::Identity() * 1e-3;
    kf.scan = r.scans[i];
    for (; next_landmark < r.landmarks.size() && r.landmarks[next_landmark].stamp_ns <= kf.stamp_ns; ++next_landmark) {
      const LandmarkObservation& o = r.landmarks[next_landmark];
      const size_t j = size_t((o.stamp_ns - r.scans[0].stamp_ns + kNsPerSec / 20) / (kNsPerSec / 10));
      kf.landmarks.push_back(reexpress_landmark(o, kf.T_local_base.between(r.odometry[j].T_odom_base)));
    }
    out.push_back(kf);
  }
  return out;
}

}  // namespace cairn::base::testing
