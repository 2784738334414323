#pragma once
// Reader for CARMEN text logs (raw and GMapping-corrected, plain or .gz): FLASER, ROBOTLASER1 and
// ODOM records; PARAM/NEFF/SYNC/comments are ignored; unknown records are counted and skipped.
//   FLASER n r1..rn x y th odom_x odom_y odom_th ipc_ts host logger_ts
//   ROBOTLASER1 type start_angle fov res max_range accuracy remission_mode n r1..rn m rem1..remm
//               laser_x laser_y laser_th robot_x robot_y robot_th tv rv fwd_safety side_safety
//               turn_axis ipc_ts host logger_ts
//   ODOM x y th tv rv accel ipc_ts host logger_ts
// FLASER beams start at -90 deg, counter-clockwise: 180/181 beams = 1 deg, 360/361 = 0.5 deg.
#include <string>
#include <vector>

#include "common/laser_scan.h"
#include "common/se2.h"
#include "common/time.h"

namespace cairn {

struct CarmenScan {
  StampNs stamp_ns = 0;  ///< ipc timestamp
  LaserScan scan;        ///< ranges >= no_return_range_m become +inf (no return)
  SE2 T_world_laser;     ///< the pose in the record (SLAM-corrected in corrected logs)
  SE2 T_odom_laser;      ///< odometry pose in the record (all zero in corrected logs)
  int line = 0;          ///< line number in the file, for messages
};

struct CarmenOdometry {
  StampNs stamp_ns = 0;
  SE2 T_odom_base;
  double linear_mps = 0, angular_radps = 0;
};

struct CarmenStats {
  int lines = 0;
  int laser_records = 0;
  int odometry_records = 0;
  int ignored_records = 0;  ///< PARAM, NEFF, SYNC, comments, blank lines
  int unknown_records = 0;  ///< record types this reader does not know
};

struct CarmenLog {
  std::vector<CarmenScan> scans;
  std::vector<CarmenOdometry> odometry;
  CarmenStats stats;
};

/// Whether a log is SLAM-corrected (GMapping output: `*corrected*` or `*.gfs.log`). In those, the
/// FLASER pose fields are the corrected trajectory and there is no raw odometry; in raw logs the
/// same fields are the wheel odometry. The record format cannot tell the two apart.
bool is_corrected_log_name(const std::string& path);

struct CarmenReadOptions {
  float no_return_range_m = 80.f;  ///< readings at or beyond are "no return" (81.91 in SICK logs)
  float range_min_m = 0.01f;
};

/// Reads a whole log. Throws InputError naming the file and line for a malformed or truncated
/// record (wrong beam count, non-numeric field, missing timestamp).
CarmenLog read_carmen_log(const std::string& path, const CarmenReadOptions& options = {});

}  // namespace cairn
