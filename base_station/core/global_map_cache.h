#pragma once
// GlobalMapCache: the merged occupancy grid kept in step with the keyframes' global poses
// (MapperData). The mapper says which keyframes may have moved, or that any may have; render()
// hands only those to the GlobalMapRenderer, which redraws only the tiles of keyframes that are
// new, gone or moved beyond its thresholds. A linked robot's keyframes are drawn at their global
// poses; an unlinked robot's are not drawn.
#include <cstdint>
#include <vector>

#include "base_station/core/global_map_renderer.h"
#include "base_station/core/mapper_data.h"

namespace cairn::base {

class GlobalMapCache {
 public:
  GlobalMapCache(const OccupancyGridOptions& grid, const GlobalMapRenderOptions& options) : renderer_(grid, options) {}

  /// These keyframes' global poses may have changed (listed: only they are re-checked).
  void moved(KeyframeId id) { moved_.push_back(id); }
  void moved(const std::vector<KeyframeId>& ids) { moved_.insert(moved_.end(), ids.begin(), ids.end()); }
  /// Any keyframe may have moved: every one is re-checked at the next render.
  void all_moved() { all_moved_ = true; }
  /// Poses changed, and what moved was listed (moved() / all_moved()).
  void poses_changed();
  /// Poses changed without a list (e.g. a robot placed): every keyframe is re-checked.
  void poses_changed_unlisted() { ++poses_version_; }
  /// A list longer than the keyframes (a map never rendered) is dropped for a full re-check.
  void bound(size_t keyframes);
  /// The grid of every linked keyframe at its current global pose.
  const OccupancyGrid& render(const MapperData& data);

 private:
  GlobalMapRenderer renderer_;
  std::vector<KeyframeId> moved_;
  bool all_moved_ = true;
  uint64_t poses_version_ = 1;  ///< bumped by every change of poses
  /// poses_version_ as far as moved_ / all_moved_ account for it: behind it, re-check everything.
  uint64_t tracked_version_ = 0;
  uint64_t rendered_version_ = 0;
};

}  // namespace cairn::base
