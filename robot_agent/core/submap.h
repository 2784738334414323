#pragma once
// Submaps as in Cartographer's local SLAM (Hess et al., "Real-Time Loop Closure in 2D LIDAR SLAM",
// ICRA 2016, Sec. IV): two overlapping active submaps; every scan goes into both; a new submap
// starts when the newest holds `scans_per_submap` scans and the oldest is finished when it holds
// twice that. Scans are matched against the oldest active submap (the more complete one).
#include <Eigen/Core>
#include <deque>
#include <vector>

#include "common/occupancy_grid.h"
#include "common/se2.h"

namespace cairn::agent {

struct SubmapOptions {
  OccupancyGridOptions grid;
  int scans_per_submap = 35;  ///< a finished submap holds twice this many scans
};

struct Submap {
  explicit Submap(const OccupancyGridOptions& grid_options, const SE2& T_local_origin)
      : grid(grid_options), T_local_submap(T_local_origin) {}
  OccupancyGrid grid;           ///< in the local map frame
  SE2 T_local_submap;           ///< pose of the first scan inserted
  int num_scans = 0;
  bool finished = false;
};

class ActiveSubmaps {
 public:
  explicit ActiveSubmaps(const SubmapOptions& options = {});

  /// Inserts one scan (points in the base frame) at `T_local_base` into the active submaps.
  void insert(const SE2& T_local_base, const std::vector<Eigen::Vector2f>& points_base);

  bool empty() const { return active_.empty(); }
  /// The submap scans are matched against (the oldest active one). Requires !empty().
  const Submap& matching_submap() const { return active_.front(); }
  /// Increases whenever the matching submap changes (cache key for its matching grids).
  int64_t matching_version() const { return version_; }
  const std::deque<Submap>& active() const { return active_; }
  const std::vector<Submap>& finished() const { return finished_; }

 private:
  SubmapOptions options_;
  std::deque<Submap> active_;
  std::vector<Submap> finished_;
  int64_t version_ = 0;
};

}  // namespace cairn::agent
