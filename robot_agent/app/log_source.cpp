#include "robot_agent/app/log_source.h"

#include "robot_agent/core/agent_pipeline.h"

namespace cairn::agent {

LogSource::LogSource(const CarmenLog& log, const LogSourceOptions& options) : scans_(log.scans), options_(options) {}

int LogSource::feed(double elapsed_wall_s, AgentPipeline* pipeline) {
  if (finished()) return 0;
  const StampNs t0 = scans_.front().stamp_ns;
  const StampNs due_ns = options_.speed > 0 ? t0 + sec_to_ns(elapsed_wall_s * options_.speed)
                                            : std::numeric_limits<StampNs>::max();
  int fed = 0;
  // Bounded batches keep the node responsive (status, acks) while replaying at full speed.
  while (!finished() && scans_[next_].stamp_ns <= due_ns && fed < 50) {
    const CarmenScan& s = scans_[next_++];
    if (options_.odometry_from_log) pipeline->add_odometry({s.stamp_ns, s.T_odom_laser, 0.0, 0.0});
    pipeline->add_scan(s.scan);
    ++fed;
  }
  return fed;
}

}  // namespace cairn::agent
