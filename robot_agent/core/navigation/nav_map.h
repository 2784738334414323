#pragma once
// The robot's own navigation map: an OccupancyGrid (0.1 m cells) in the robot's local frame into
// which every processed scan is inserted at its SLAM pose. Coarser than the SLAM submaps (planning
// needs no more), with log odds clamped tighter so rubble that appears, or an obstacle that
// leaves, changes a cell within a few scans. Teammates (bright beams) are not walls. Pure: scans
// in, a grid out.
#include "common/laser_scan.h"
#include "common/occupancy_grid.h"
#include "common/se2.h"

namespace cairn::agent {

struct NavMapOptions {
  double resolution_m = 0.1;
  double max_range_m = 8.0;  ///< beams are cut here: far walls seen through gaps matter little to driving
  /// Beams without a return clear free space this far (0: not at all).
  double no_return_clear_m = 4.0;
  /// One hit outweighs a neighbouring beam grazing the cell (a miss) and makes it occupied (p 0.69).
  float hit_log_odds = 1.2f;
  float miss_log_odds = -0.4f;
  float min_log_odds = -2.0f;  ///< ~3 hits turn a well-seen free cell occupied
  float max_log_odds = 3.5f;
  /// Beams at least this bright hit a teammate's reflective tape (AgentOptions::teammate_min_intensity,
  /// the same threshold): a teammate moves on, so its beam clears the free space up to it and marks
  /// nothing occupied (the path follower still stops for it: it reads the scan itself). Marked as
  /// walls, teammates crossing a doorway closed it for good: on the building site robots spent a
  /// minute refusing every goal behind doors their own maps had closed. 0: every beam a wall.
  float teammate_min_intensity = 0.9f;
  double teammate_clear_short_m = 0.1;  ///< a teammate's beam clears up to this short of the hit
};

class NavMap {
 public:
  explicit NavMap(const NavMapOptions& options = {});

  /// Inserts `scan` taken at `T_local_base` (the laser is at the base's origin, sensors.h).
  void insert(const SE2& T_local_base, const LaserScan& scan);
  const OccupancyGrid& grid() const { return grid_; }
  int scans_inserted() const { return scans_; }
  const NavMapOptions& options() const { return options_; }

 private:
  NavMapOptions options_;
  OccupancyGrid grid_;
  int scans_ = 0;
};

}  // namespace cairn::agent
