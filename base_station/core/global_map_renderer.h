#pragma once
// GlobalMapRenderer: the base station's global occupancy grid, kept up to date incrementally.
// Every keyframe's scan is ray-cast at its global pose, in keyframe id order (as a full render
// would). The world is cut into square tiles; each keyframe is indexed under the tiles its scan
// footprint (sensor origin + beam ends) overlaps. When a keyframe is added, removed or moves by more
// than min_move_m / min_turn_rad from the pose it was drawn at, the tiles of its old and new
// footprints are cleared and re-rendered from the keyframes overlapping them, each clipped to the
// tile. A re-rendered tile is identical to a full render at the drawn poses (same cells, same
// update order), so the cost of an update is that of the tiles that changed, not of the whole map.
#include <cmath>
#include <map>
#include <set>
#include <vector>

#include "common/ids.h"
#include "common/keyframe.h"
#include "common/occupancy_grid.h"

namespace cairn::base {

struct GlobalMapRenderOptions {
  double tile_m = 16.0;         ///< side of a re-render tile (rounded to whole grid cells)
  double min_move_m = 0.03;     ///< a keyframe is redrawn when it moved more than this...
  double min_turn_rad = 0.003;  ///< ...or turned more than this (0.17 deg: ~3 cm at 10 m)
  /// Max-range beams (no return) clear free space up to min(scan range_max, this).
  double no_return_clear_range_m = 10.0;
};

struct GlobalMapRenderStats {
  int keyframes_drawn = 0;  ///< keyframes (re)drawn by the last render(), counted once per tile
  int tiles = 0;            ///< tiles re-rendered by the last render()
};

class GlobalMapRenderer {
 public:
  GlobalMapRenderer(const OccupancyGridOptions& grid, const GlobalMapRenderOptions& options);

  /// Keyframe `kf` should appear at T_global_base (its beams are copied on first sight: a
  /// keyframe id's scan never changes).
  void set_pose(const Keyframe& kf, const SE2& T_global_base);
  void remove(KeyframeId id);
  bool contains(KeyframeId id) const { return drawn_.count(id) > 0; }
  /// Applies the pending changes (re-renders the changed tiles) and returns the grid.
  const OccupancyGrid& render();
  const GlobalMapRenderStats& last_stats() const { return stats_; }

 private:
  using Tile = std::pair<int, int>;  ///< (x, y) tile index
  struct Drawn {
    SE2 T_global_base;
    std::vector<Eigen::Vector2f> hits, no_return;  ///< beam ends in the sensor frame
    Eigen::Vector2d lo_m = Eigen::Vector2d::Constant(NAN),
                    hi_m;  ///< footprint (origin and beam ends); NaN: never drawn
    Tile lo, hi;           ///< inclusive tile range of the footprint (one cell of margin)
  };
  Tile tile_of(const Eigen::Vector2d& p_m) const;
  void footprint(Drawn* d) const;
  void index(KeyframeId id, const Drawn& d, bool add);
  void mark_dirty(const Drawn& d);
  /// Grows the grid to hold [lo_m, hi_m], by at least a quarter of its size per side that grows.
  void grow_for(const Eigen::Vector2d& lo_m, const Eigen::Vector2d& hi_m);

  OccupancyGridOptions grid_options_;
  GlobalMapRenderOptions options_;
  double tile_m_;
  OccupancyGrid grid_;
  std::map<KeyframeId, Drawn> drawn_;
  std::map<Tile, std::set<KeyframeId>> tiles_;  ///< keyframes whose footprint overlaps a tile
  std::set<Tile> dirty_;
  std::vector<KeyframeId> appended_;  ///< new keyframes not drawn yet
  GlobalMapRenderStats stats_;
};

}  // namespace cairn::base
