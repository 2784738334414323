#pragma once
// Offline 2D SLAM over a CARMEN log (tools/slam): feeds every scan, with its odometry, through the
// robot agent's LocalSlam (the same core the agent runs), as fast as it can, and renders the final
// map from the optimised poses. Corrected logs (no raw odometry) get seeded synthetic odometry
// noise (common/odometry_noise.h) so they stand in for raw logs.
#include <optional>
#include <string>

#include "common/carmen_log.h"
#include "common/multirobot_log.h"
#include "common/occupancy_grid.h"
#include "common/odometry_noise.h"
#include "common/trajectory.h"
#include "robot_agent/core/local_slam.h"

namespace cairn::slam {

struct SlamRunOptions {
  agent::LocalSlamOptions slam;
  /// Odometry for corrected logs: noise added to the corrected trajectory.
  OdometryNoiseOptions noise;
  bool use_odometry = true;
  /// Robustness runs: the odometry freezes at its reading before scan `first` until scan `last`
  /// (inclusive), as a dead or late odometry stream does in the agent; -1: none.
  int odometry_dropout_first = -1, odometry_dropout_last = -1;
  OccupancyGridOptions map;  ///< the rendered map
};

struct SlamRunStats {
  int scans = 0, matched = 0, motion_filtered = 0, match_failed = 0, too_few_points = 0;
  int odometry_stalled = 0;  ///< skipped: the odometry held its reading while the scan moved
  int nodes = 0, submaps = 0, loop_closures = 0, loop_searches = 0, optimizations = 0;
  int anisotropic_loop_closures = 0, anisotropic_local_nodes = 0;  ///< covariance weighting, ratio < 1/2
  int64_t loop_scored_candidates = 0, loop_scored_candidates_failed = 0;
  double loop_matcher_mb = 0;
  ScanFilterStats beams;
  double log_duration_s = 0;
  double slam_wall_s = 0, slam_cpu_s = 0;
  double slam_sys_cpu_s = 0;                             ///< kernel part of slam_cpu_s (mostly page faults)
  int64_t slam_minor_faults = 0, slam_major_faults = 0;  ///< page faults during the SLAM loop
  double scans_per_s() const { return slam_wall_s > 0 ? scans / slam_wall_s : 0; }
  double real_time_factor() const { return slam_wall_s > 0 ? log_duration_s / slam_wall_s : 0; }
};

struct SlamRunResult {
  Trajectory trajectory;  ///< every scan, optimised frame
  Trajectory odometry;    ///< the odometry fed in (noisy for corrected logs)
  SlamRunStats stats;
};

/// Runs the SLAM over a log. `corrected`: the log's poses are a reference, not odometry.
SlamRunResult run_slam(const CarmenLog& log, bool corrected, const SlamRunOptions& options);

/// One robot of a Cairn multi-robot log (e.g. a simulated world recorded by `cairn_mrlog
/// from-world`, whose TRUTH records are exact) as a raw CARMEN log: its scans, each with the robot's
/// odometry interpolated at the scan's stamp in the pose fields. Scans outside the odometry's span
/// are dropped. Throws InputError when the robot has no odometry or no scan within it.
CarmenLog carmen_log_from_robot(const RobotLogData& robot);

/// Occupancy map of all scans placed at `trajectory` (matched by stamp).
OccupancyGrid render_map(const CarmenLog& log, const Trajectory& trajectory, const OccupancyGridOptions& options);

/// Process CPU time (user + system) and peak resident memory.
double process_cpu_s();
double peak_rss_mb();

}  // namespace cairn::slam
