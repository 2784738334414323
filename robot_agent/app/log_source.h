#pragma once
// Feeds a CARMEN log to the agent in place of the sensor topics: each laser record becomes a scan
// and, for raw logs, an odometry reading (the FLASER pose fields are the wheel odometry there).
// Corrected logs carry no raw odometry; their readings are scans only unless the caller supplies
// odometry (e.g. with seeded noise). Replays as fast as possible or at a multiple of real time.
#include <deque>
#include <string>

#include "common/carmen_log.h"
#include "common/sensors.h"

namespace cairn::agent {

class AgentPipeline;

struct LogSourceOptions {
  double speed = 0.0;            ///< times real time; 0 = as fast as the pipeline takes it
  bool odometry_from_log = true; ///< raw logs: FLASER odom fields become odometry readings
};

class LogSource {
 public:
  LogSource(const CarmenLog& log, const LogSourceOptions& options);
  /// Adds the readings that are due after `elapsed_wall_s` to the pipeline. Returns how many.
  int feed(double elapsed_wall_s, AgentPipeline* pipeline);
  bool finished() const { return next_ >= scans_.size(); }
  size_t size() const { return scans_.size(); }

 private:
  std::vector<CarmenScan> scans_;
  LogSourceOptions options_;
  size_t next_ = 0;
};

}  // namespace cairn::agent
