#pragma once
// Feeds a recorded log to the agent in place of the sensor topics, as fast as possible or at a
// multiple of real time. Two sources:
// - a CARMEN log: each laser record becomes a scan and, for raw logs, an odometry reading (the
//   FLASER pose fields are the wheel odometry there). Corrected logs carry no raw odometry; their
//   readings are scans only unless the caller supplies odometry (e.g. with seeded noise).
// - one robot of a Cairn multi-robot log (common/multirobot_log.h): its odometry, scans and
//   identified landmark observations, merged in stamp order (at equal stamps odometry, then the
//   scan, then landmarks), so the landmarks reach the keyframes (AgentPipeline::add_landmark).
#include <string>
#include <vector>

#include "common/carmen_log.h"
#include "common/multirobot_log.h"
#include "common/sensors.h"

namespace cairn::agent {

class AgentPipeline;

struct LogSourceOptions {
  double speed = 0.0;             ///< times real time; 0 = as fast as the pipeline takes it
  bool odometry_from_log = true;  ///< feed the log's odometry (CARMEN: the FLASER odom fields)
};

class LogSource {
 public:
  LogSource(const CarmenLog& log, const LogSourceOptions& options);
  LogSource(const RobotLogData& robot, const LogSourceOptions& options);
  /// Adds the readings that are due after `elapsed_wall_s` to the pipeline. Returns how many.
  int feed(double elapsed_wall_s, AgentPipeline* pipeline);
  bool finished() const { return next_ >= events_.size(); }
  size_t size() const { return scans_.size(); }  ///< laser scans
  size_t landmarks() const { return landmarks_.size(); }

 private:
  enum class Kind { kOdometry, kScan, kLandmark };
  struct Event {
    StampNs stamp_ns;
    Kind kind;
    size_t index;
  };

  LogSourceOptions options_;
  std::vector<OdometryReading> odometry_;
  std::vector<LaserScan> scans_;
  std::vector<LandmarkObservation> landmarks_;
  std::vector<Event> events_;  ///< in feeding order
  size_t next_ = 0;
};

}  // namespace cairn::agent
