#pragma once
// Test support for the real multi-robot split (tests/multirobot): one CARMEN log cut into K
// contiguous segments, each replayed as its own robot (odometry re-zeroed, so every robot starts
// at its own origin) through an AgentPipeline, and the keyframes merged by a MultiRobotMapper that
// knows robot 0's start only. Also the reference pose of every scan (world frame of the log).
#include <string>
#include <vector>

#include "base_station/core/multi_robot_mapper.h"
#include "common/carmen_log.h"
#include "common/keyframe.h"
#include "common/trajectory.h"

namespace cairn::multirobot {

struct ReplayLog {
  std::vector<CarmenScan> scans;
  std::vector<SE2> odometry;   ///< per scan, odometry frame of the whole log
  std::vector<SE2> reference;  ///< per scan, reference pose (world frame of the log)
  /// Per scan, the nearest scan whose reference is measured (a corrected scan), not carried by
  /// odometry; -1 when there is none.
  std::vector<int> measured_reference;
};

/// Raw log + GMapping-corrected twin: reference from the corrected scan with identical ranges,
/// carried to the scans in between by the (locally accurate) odometry. Empty if nothing matches.
ReplayLog replay_from_raw(const CarmenLog& raw, const CarmenLog& corrected, int* matched);
/// Corrected log: reference = its poses; odometry = seeded noise on them (common/odometry_noise.h).
ReplayLog replay_from_corrected(const CarmenLog& corrected, uint32_t seed);

struct RobotRun {
  std::vector<Keyframe> keyframes;
  std::vector<SE2> reference;  ///< per keyframe (world frame of the log)
  /// Per keyframe, the reference closures are judged by: the nearest measured reference in this
  /// robot's segment, carried to the keyframe by the agent's own scan-matched poses (1-2 scans on
  /// MIT CSAIL, centimetres and tenths of a degree) instead of by odometry, whose interpolated yaw
  /// is off by degrees (ReplayLog::reference).
  std::vector<SE2> closure_reference;
  /// The agent's loop-closed keyframe poses as it sent them, each with the number of keyframes
  /// it had emitted by then (merge() hands them to the base at that point).
  std::vector<std::pair<size_t, KeyframePoses>> keyframe_poses;
};

/// Replays scans [begin, end) as robot `robot`: odometry re-zeroed at `begin`.
RobotRun run_agent(const ReplayLog& log, size_t begin, size_t end, RobotId robot);
/// K contiguous segments of equal scan count.
std::vector<RobotRun> run_split(const ReplayLog& log, int robots);

struct MergeStats {
  int optimizations = 0;
  double max_optimize_s = 0;
  std::vector<base::LinkEvent> link_events;  ///< every link decision, in order
};
/// Feeds the robots' keyframes interleaved by their position in each run (robots explore at the
/// same time), optimising every `optimize_every` keyframes; robot 0's start is the only hint.
MergeStats merge(const std::vector<RobotRun>& runs, base::MultiRobotMapper* mapper, int optimize_every = 25);

/// ATE (RMSE, metres) of every linked keyframe's global pose against its reference, after one
/// best SE2 alignment of the whole map. `matched` gets the number of keyframes compared.
double merged_ate_m(const std::vector<RobotRun>& runs, const base::MultiRobotMapper& mapper, int* matched);

/// Translation / rotation error of a closure against RobotRun::closure_reference.
struct ClosureError {
  double translation_m = 0, rotation_rad = 0;
};
ClosureError closure_error(const base::LoopClosure& c, const std::vector<RobotRun>& runs);

}  // namespace cairn::multirobot
