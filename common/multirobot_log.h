#pragma once
// The Cairn multi-robot text log (docs/multirobot_log_format.md): one plain line-based file holding
// several robots' odometry, laser scans and identified landmark observations, so that any dataset
// can be converted into it (tools/mrlog) and replayed through the agents and the base station
// (`cairn_agent --log file --robot N`). Records:
//   CAIRN_MRLOG <version>                                         (first record, version 1)
//   ODOM     <robot> <t_s> <x_m> <y_m> <yaw_rad>
//   SCAN     <robot> <t_s> <angle_min_rad> <angle_increment_rad> <range_max_m> <n> r1..rn
//   LANDMARK <robot> <t_s> <id> <range_m> <bearing_rad> <sigma_range_m> <sigma_bearing_rad>
//   TRUTH    <robot> <t_s> <x_m> <y_m> <yaw_rad>                  (optional reference pose, world frame)
//   MARKER   <id> <x_m> <y_m>                                     (optional reference landmark position)
// `#` starts a comment; blank lines are ignored. Ranges may be `inf` (no return) or `nan` (a broken
// reading, counted); landmark and pose values must be finite.
#include <iosfwd>
#include <map>
#include <string>
#include <vector>

#include "common/ids.h"
#include "common/landmark_observation.h"
#include "common/laser_scan.h"
#include "common/sensors.h"
#include "common/trajectory.h"

namespace cairn {

constexpr int kMultiRobotLogVersion = 1;

/// One robot's readings, each list in non-decreasing stamp order (the reader enforces it).
struct RobotLogData {
  RobotId robot;
  std::vector<OdometryReading> odometry;  ///< T_odom_base (linear/angular speeds left 0)
  std::vector<LaserScan> scans;
  std::vector<LandmarkObservation> landmarks;
  Trajectory truth;  ///< optional reference poses (common world frame)
};

struct MultiRobotLogStats {
  int lines = 0;
  int records = 0;
  int nan_ranges = 0;  ///< NaN beams read (kept as NaN: the scan filter counts and drops them)
  int inf_ranges = 0;  ///< +inf beams (no return)
};

struct MultiRobotLog {
  int version = kMultiRobotLogVersion;
  std::map<RobotId, RobotLogData> robots;
  std::map<LandmarkId, Eigen::Vector2d> markers;  ///< optional reference positions (world frame)
  MultiRobotLogStats stats;

  /// nullptr when the log holds nothing for `robot`.
  const RobotLogData* robot(RobotId id) const {
    auto it = robots.find(id);
    return it == robots.end() ? nullptr : &it->second;
  }
  /// Adds (or returns) the robot's entry.
  RobotLogData& robot_data(RobotId id) {
    RobotLogData& r = robots[id];
    r.robot = id;
    return r;
  }
};

struct MultiRobotLogReadOptions {
  float range_min_m = 0.01f;  ///< LaserScan::range_min_m of every scan read
  int max_beams = 8192;
};

/// Parses a log from `in`; `name` names it in errors. Throws InputError "name:line: what is wrong"
/// for a missing/unsupported header, an unknown record, a missing or non-numeric field, a non-finite
/// pose or landmark value, a negative sigma, a beam count that does not match, trailing fields, or a
/// stamp older than the robot's previous record of the same type.
MultiRobotLog parse_multirobot_log(std::istream& in, const std::string& name,
                                   const MultiRobotLogReadOptions& options = {});
/// Reads a file (see parse_multirobot_log); throws InputError if it cannot be opened.
MultiRobotLog read_multirobot_log(const std::string& path, const MultiRobotLogReadOptions& options = {});

/// Whether the file starts (after comments and blank lines) with the CAIRN_MRLOG header.
bool is_multirobot_log(const std::string& path);

/// Writes the log with every record of every robot merged in time order (at equal stamps: ODOM,
/// SCAN, LANDMARK, TRUTH; then by robot). `comment` lines are written after the header as `# ...`.
void write_multirobot_log(std::ostream& out, const MultiRobotLog& log, const std::string& comment = {});
/// Returns false on I/O failure.
bool write_multirobot_log_file(const std::string& path, const MultiRobotLog& log, const std::string& comment = {});

}  // namespace cairn
