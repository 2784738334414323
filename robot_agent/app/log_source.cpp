#include "robot_agent/app/log_source.h"

#include <algorithm>
#include <limits>

#include "robot_agent/core/agent_pipeline.h"

namespace cairn::agent {

LogSource::LogSource(const CarmenLog& log, const LogSourceOptions& options) : options_(options) {
  // File order (the pipeline counts and drops out-of-order scans itself).
  for (const CarmenScan& s : log.scans) {
    if (options_.odometry_from_log) {
      events_.push_back({s.stamp_ns, Kind::kOdometry, odometry_.size()});
      odometry_.push_back({s.stamp_ns, s.T_odom_laser, 0.0, 0.0});
    }
    events_.push_back({s.stamp_ns, Kind::kScan, scans_.size()});
    scans_.push_back(s.scan);
  }
}

LogSource::LogSource(const RobotLogData& robot, const LogSourceOptions& options)
    : options_(options), scans_(robot.scans), landmarks_(robot.landmarks) {
  if (options_.odometry_from_log) odometry_ = robot.odometry;
  for (size_t i = 0; i < odometry_.size(); ++i) events_.push_back({odometry_[i].stamp_ns, Kind::kOdometry, i});
  for (size_t i = 0; i < scans_.size(); ++i) events_.push_back({scans_[i].stamp_ns, Kind::kScan, i});
  for (size_t i = 0; i < landmarks_.size(); ++i) events_.push_back({landmarks_[i].stamp_ns, Kind::kLandmark, i});
  std::stable_sort(events_.begin(), events_.end(), [](const Event& a, const Event& b) {
    return a.stamp_ns != b.stamp_ns ? a.stamp_ns < b.stamp_ns : a.kind < b.kind;
  });
}

int LogSource::feed(double elapsed_wall_s, AgentPipeline* pipeline) {
  if (finished()) return 0;
  const StampNs t0 = events_.front().stamp_ns;
  const StampNs due_ns =
      options_.speed > 0 ? t0 + sec_to_ns(elapsed_wall_s * options_.speed) : std::numeric_limits<StampNs>::max();
  int fed = 0;
  // Bounded batches keep the node responsive (status, acks) while replaying at full speed.
  while (!finished() && events_[next_].stamp_ns <= due_ns && fed < 100) {
    const Event& e = events_[next_++];
    switch (e.kind) {
      case Kind::kOdometry:
        pipeline->add_odometry(odometry_[e.index]);
        break;
      case Kind::kScan:
        pipeline->add_scan(scans_[e.index]);
        break;
      case Kind::kLandmark:
        pipeline->add_landmark(landmarks_[e.index]);
        break;
    }
    ++fed;
  }
  return fed;
}

}  // namespace cairn::agent
