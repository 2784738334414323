#pragma once
// Converters into the Cairn multi-robot text log (common/multirobot_log.h,
// docs/multirobot_log_format.md), used by cairn_mrlog:
// - a simulated world (worlds/*.yaml): the simulator is stepped headless (no camera) and each
//   robot's odometry, laser scans, reference poses and range-bearing observations of the world's
//   objects (marker id = object id, seen within range and field of view with a clear line of sight
//   through the floor plan, seeded noise) are recorded, with the objects as MARKER records.
// - CARMEN logs: one log cut into K contiguous segments, one robot each (odometry re-zeroed so every
//   robot starts at its own origin), or several logs, one robot each. GMapping-corrected logs have
//   no raw odometry: their poses become TRUTH records and the odometry is the reference with seeded
//   noise (common/odometry_noise.h). Optional virtual markers along the reference path (corrected
//   logs only) give real-scan datasets identified landmarks to link robots with.
#include <cstdint>
#include <string>
#include <vector>

#include "common/carmen_log.h"
#include "common/multirobot_log.h"
#include "sim/world.h"

namespace cairn::mrlog {

struct LandmarkSensorOptions {
  double max_range_m = 5.0;
  double min_range_m = 0.3;
  double fov_rad = 2.0 * M_PI;  ///< centred on the robot's heading
  double rate_hz = 2.0;
  double sigma_range_m = 0.05;  ///< noise drawn and written as the observation's sigma
  double sigma_bearing_rad = 0.02;
  uint64_t seed = 11;
};

struct WorldRecordOptions {
  LandmarkSensorOptions landmarks;
  double duration_s = 0.0;   ///< 0 = the world file's
  bool featureless = false;  ///< every beam "no return": only the markers can link robots
  std::vector<int> robots;   ///< empty = every robot of the world
};

/// Steps the simulator over `world` and records the log. Throws InputError for an unknown robot id.
MultiRobotLog record_world(const sim::WorldFile& world, const WorldRecordOptions& options);

struct CarmenConvertOptions {
  int split = 1;                          ///< one log: this many contiguous robots
  uint32_t odometry_noise_seed = 1;       ///< corrected logs: synthetic odometry
  double virtual_marker_spacing_m = 0.0;  ///< > 0: markers every this far along the reference path
  double virtual_marker_offset_m = 1.0;   ///< to the left of the path
  LandmarkSensorOptions landmarks{4.0, 0.3, 2.0 * M_PI, 0.0, 0.05, 0.02, 11};  ///< rate 0 = every scan
};

/// Converts `logs` (one robot each), or logs[0] split into options.split robots. `corrected[i]`
/// says whether logs[i] is GMapping-corrected (see is_corrected_log_name). Throws InputError when a
/// log has no scans, split < 1, or virtual markers are asked for without a reference trajectory.
MultiRobotLog convert_carmen(const std::vector<CarmenLog>& logs, const std::vector<bool>& corrected,
                             const CarmenConvertOptions& options);

}  // namespace cairn::mrlog
