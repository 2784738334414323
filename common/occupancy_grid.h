#pragma once
// A log-odds occupancy grid that grows to fit what is inserted. Used for the robot's submaps, the
// base station's global map and the simulator's floor plan. Rows grow with +y, columns with +x;
// cell (0,0) has its lower-left corner at origin_m().
#include <Eigen/Core>
#include <climits>
#include <cstdint>
#include <string>
#include <vector>

#include "common/se2.h"

namespace cairn {

struct OccupancyGridOptions {
  double resolution_m = 0.05;
  float hit_log_odds = 0.85f;    ///< added to a cell that a beam ends in (p_hit ~ 0.70)
  float miss_log_odds = -0.40f;  ///< added to each cell a beam passes through (p_miss ~ 0.40)
  float min_log_odds = -4.0f;
  float max_log_odds = 4.0f;
  double max_range_m = 30.0;  ///< beams are cut to this length before ray casting
};

class OccupancyGrid {
 public:
  explicit OccupancyGrid(const OccupancyGridOptions& options = {});
  /// A grid with fixed initial bounds (it still grows when needed).
  OccupancyGrid(const OccupancyGridOptions& options, const Eigen::Vector2d& min_m, const Eigen::Vector2d& max_m);

  /// Ray-casts each beam: cells along the beam get a miss, the endpoint cell a hit.
  /// `points_sensor` are beam endpoints in the sensor frame; `T_map_sensor` places the sensor.
  /// `no_return_points_sensor` (optional) clear free space along max-range beams without a hit.
  void insert_scan(const SE2& T_map_sensor, const std::vector<Eigen::Vector2f>& points_sensor,
                   const std::vector<Eigen::Vector2f>& no_return_points_sensor = {});
  /// insert_scan restricted to the cells whose centres lie in [clip_min_m, clip_max_m): cells
  /// outside are left untouched, cells inside get exactly the updates insert_scan would give them
  /// (used to re-render one tile of a map).
  void insert_scan_clipped(const SE2& T_map_sensor, const std::vector<Eigen::Vector2f>& points_sensor,
                           const std::vector<Eigen::Vector2f>& no_return_points_sensor,
                           const Eigen::Vector2d& clip_min_m, const Eigen::Vector2d& clip_max_m);
  /// Grows the grid (once) to cover [min_m, max_m], e.g. before many insertions.
  void reserve(const Eigen::Vector2d& min_m, const Eigen::Vector2d& max_m) { ensure_contains(min_m, max_m); }
  /// Sets the cells whose centres lie in [min_m, max_m) back to unknown (the grid does not grow).
  void clear_region(const Eigen::Vector2d& min_m, const Eigen::Vector2d& max_m);
  /// Marks a single cell (e.g. drawing a floor plan).
  void update_cell(int col, int row, float delta_log_odds);

  int width() const { return width_; }
  int height() const { return height_; }
  double resolution_m() const { return options_.resolution_m; }
  Eigen::Vector2d origin_m() const { return origin_m_; }
  const OccupancyGridOptions& options() const { return options_; }

  bool contains(int col, int row) const { return col >= 0 && row >= 0 && col < width_ && row < height_; }
  /// Cell holding world point p (may be outside the grid).
  Eigen::Vector2i cell_of(const Eigen::Vector2d& p_m) const;
  Eigen::Vector2d cell_center_m(int col, int row) const;

  float log_odds(int col, int row) const;  ///< 0 (unknown) outside the grid
  bool known(int col, int row) const { return log_odds(col, row) != 0.f; }
  double probability(int col, int row) const;
  /// No cell with occupancy probability above `occupied_above` on the straight line a-b (unknown
  /// cells, and cells outside the grid, do not block): whether a robot at a could see one at b.
  bool line_clear(const Eigen::Vector2d& a_m, const Eigen::Vector2d& b_m, double occupied_above = 0.65) const;
  /// Area of cells that were observed (free or occupied), square metres.
  double known_area_m2() const;

  /// ROS map_server convention, top row first: 0 occupied, 254 free, 205 unknown.
  std::vector<uint8_t> to_image(double occupied_threshold = 0.65, double free_threshold = 0.25) const;
  /// Writes `<stem>.pgm` and `<stem>.yaml` (map_server format). Returns false on I/O failure.
  bool write_pgm_yaml(const std::string& stem) const;

 private:
  void ensure_contains(const Eigen::Vector2d& min_m, const Eigen::Vector2d& max_m);
  void trace_ray(const Eigen::Vector2i& from, const Eigen::Vector2i& to, bool hit_at_end);
  void insert_scan_impl(const SE2& T_map_sensor, const std::vector<Eigen::Vector2f>& points,
                        const std::vector<Eigen::Vector2f>& no_return_points, const Eigen::Vector2d* clip_min_m,
                        const Eigen::Vector2d* clip_max_m);
  /// Cell range [lo, hi) whose centres lie in [min_m, max_m), clamped to the grid.
  void cell_range(const Eigen::Vector2d& min_m, const Eigen::Vector2d& max_m, Eigen::Vector2i* lo,
                  Eigen::Vector2i* hi) const;
  float& at(int col, int row) { return cells_[size_t(row) * width_ + col]; }

  OccupancyGridOptions options_;
  Eigen::Vector2d origin_m_ = Eigen::Vector2d::Zero();
  int width_ = 0;
  int height_ = 0;
  std::vector<float> cells_;  ///< log odds, 0 = unknown
  /// While insert_scan_clipped runs: only cells in [clip_lo_, clip_hi_) are updated.
  Eigen::Vector2i clip_lo_{INT32_MIN, INT32_MIN};
  Eigen::Vector2i clip_hi_{INT32_MAX, INT32_MAX};
};

}  // namespace cairn
