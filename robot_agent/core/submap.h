#pragma once
// Submaps as in Cartographer's local SLAM (Hess et al., "Real-Time Loop Closure in 2D LIDAR SLAM",
// ICRA 2016, Sec. IV): two overlapping active submaps, each a ProbabilityGrid updated incrementally;
// every scan goes into both; a new submap starts when the newest holds `scans_per_submap` scans and
// the oldest is finished when it holds twice that. Scans are matched against the oldest active
// submap (the more complete one).
#include <Eigen/Core>
#include <deque>
#include <memory>
#include <vector>

#include "common/se2.h"
#include "robot_agent/core/probability_grid.h"
#include "robot_agent/core/range_data_inserter.h"

namespace cairn::agent {

struct SubmapOptions {
  double resolution_m = 0.05;
  RangeDataInserterOptions inserter;
  int scans_per_submap = 35;  ///< a finished submap holds twice this many scans
  /// ... or a new submap starts once the newest has seen this much travel (sparse logs), so a
  /// submap never spans so much motion that its own drift blurs it.
  double travel_per_submap_m = 6.0;
  double initial_size_m = 20.0;  ///< initial grid extent at least, around the first scan's pose
  /// ... and around the first scan's bounding box (grows as needed; 8 m measured no faster: a larger
  /// grid costs as much in page faults as the growth copies it saves).
  double initial_margin_m = 3.0;
};

struct Submap {
  int id = 0;            ///< 0, 1, 2, ... in creation order
  ProbabilityGrid grid;  ///< in the local map frame
  SE2 T_local_submap;    ///< pose of the first scan inserted
  int num_scans = 0;
  double travel_m = 0.0;  ///< distance between the inserted scans' poses
  bool finished = false;
};

/// What one insertion did.
struct SubmapInsertion {
  std::vector<int> inserted_into;          ///< submap ids
  bool created = false;                    ///< a new submap was started (the last id in inserted_into)
  std::shared_ptr<const Submap> finished;  ///< the submap finished by this insertion, if any
};

class ActiveSubmaps {
 public:
  explicit ActiveSubmaps(const SubmapOptions& options = {});

  /// Inserts one scan (points in the base frame) at `T_local_base` into the active submaps.
  SubmapInsertion insert(const SE2& T_local_base, const std::vector<Eigen::Vector2f>& points_base);

  bool empty() const { return active_.empty(); }
  /// The submap scans are matched against (the oldest active one). Requires !empty().
  const Submap& matching_submap() const { return *active_.front(); }
  /// Increases whenever the matching submap changes.
  int64_t matching_version() const { return version_; }
  const std::deque<std::shared_ptr<Submap>>& active() const { return active_; }
  const std::vector<std::shared_ptr<const Submap>>& finished() const { return finished_; }

 private:
  SubmapOptions options_;
  RangeDataInserter inserter_;
  std::deque<std::shared_ptr<Submap>> active_;
  std::vector<std::shared_ptr<const Submap>> finished_;
  int64_t version_ = 0;
  int next_id_ = 0;
  SE2 last_pose_;
};

}  // namespace cairn::agent
