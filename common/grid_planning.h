#pragma once
// Planning on an occupancy grid, shared by the base's exploration (base_station/core/exploration.h)
// and the robot's navigation (robot_agent/core/navigation/): the grid classified into unknown /
// free / occupied within the known cells' bounding box, near-wall marks, an inflated obstacle layer
// (cells the robot's centre must not enter), frontier pieces (free cells with an unknown
// 4-neighbour, Yamauchi 1997, in 8-connected pieces), Dijkstra path lengths from a start cell with
// parents, path extraction and the nearest reachable frontier. Pure: a grid in, numbers out.
//
// Cost: a classification touches every cell of the known box once; Dijkstra every reachable cell.
// A 40 m x 30 m map at 0.05 m is 0.48 M cells; GridPlanningOptions::cell_m plans on a coarser copy
// (e.g. 0.1 m: a quarter of the cells) when the map's own cells are finer than planning needs.
#include <Eigen/Core>
#include <cstdint>
#include <functional>
#include <limits>
#include <optional>
#include <vector>

#include "common/keep_out.h"
#include "common/occupancy_grid.h"

namespace cairn {

enum class CellState : uint8_t { kUnknown, kFree, kOccupied };

struct GridPlanningOptions {
  double free_below = 0.25;      ///< a known cell below this occupancy probability is free
  double occupied_above = 0.65;  ///< above it, occupied; in between, unknown
  /// Plan on a coarser copy with cells of round(cell_m / map resolution) map cells a side (an
  /// occupied map cell makes its coarse cell occupied, else a free one makes it free). 0, or not
  /// coarser than the map: the map's own cells.
  double cell_m = 0.0;
  double clearance_m = 0.25;    ///< cells within this of an occupied cell (square) are near a wall
  double near_wall_cost = 4.0;  ///< a step into a near-wall cell costs this many times more
  /// Instead: the cost falls linearly from near_wall_cost at a wall to 1 at clearance_m (Euclidean,
  /// between cell centres), so paths keep to the middle of doors and corridors narrower than twice
  /// the clearance.
  bool graded_clearance = false;
  /// Cells whose centre lies within this distance of an occupied cell's centre are blocked (the
  /// robot's radius plus a margin of at least half a cell's diagonal). 0: only occupied cells block.
  double inflation_m = 0.0;
  /// A step into an unknown cell costs this many times more; 0: unknown cells are not traversable.
  double unknown_cost = 0.0;
  /// The planned box is the known cells' bounding box (and the points passed to PlanningGrid) grown
  /// by this on every side, at least one cell.
  double margin_m = 0.0;
};

/// An OccupancyGrid classified for planning. Cell (0, 0) is the lower-left cell of the planned box;
/// cells outside the box count as unknown. Empty when nothing is known and no point was given.
class PlanningGrid {
 public:
  PlanningGrid() = default;
  /// `include_m`: points the box must contain besides the known cells (e.g. a robot and its goal
  /// in unknown space).
  explicit PlanningGrid(const OccupancyGrid& map, const GridPlanningOptions& options = {},
                        const std::vector<Eigen::Vector2d>& include_m = {});

  bool empty() const { return w_ == 0; }
  int width() const { return w_; }
  int height() const { return h_; }
  size_t size() const { return cells_.size(); }
  double resolution_m() const { return res_; }
  const GridPlanningOptions& options() const { return options_; }

  bool in(int c, int r) const { return c >= 0 && r >= 0 && c < w_ && r < h_; }
  bool in(const Eigen::Vector2i& cell) const { return in(cell.x(), cell.y()); }
  size_t index(int c, int r) const { return size_t(r) * w_ + c; }
  size_t index(const Eigen::Vector2i& cell) const { return index(cell.x(), cell.y()); }
  Eigen::Vector2i cell(size_t index) const { return {int(index % w_), int(index / w_)}; }
  /// Centre of a cell, in the map's frame (metres).
  Eigen::Vector2d centre_m(const Eigen::Vector2i& cell) const;
  /// The cell holding a point (may lie outside the box).
  Eigen::Vector2i cell_of(const Eigen::Vector2d& p_m) const;

  CellState state(size_t i) const { return cells_[i]; }
  /// Within the clearance of an occupied cell.
  bool near_wall(size_t i) const {
    return options_.graded_clearance ? wall_distance_m(i) < options_.clearance_m : near_wall_[i] != 0;
  }
  /// Occupied, or within inflation_m of an occupied cell.
  bool blocked(size_t i) const { return cells_[i] == CellState::kOccupied || wall_distance_m(i) <= inflation_m_; }
  /// Distance between the cell's centre and the nearest occupied cell's, when within the inflation
  /// (or graded clearance) radius; +inf beyond.
  float wall_distance_m(size_t i) const {
    return wall_distance_m_.empty() ? std::numeric_limits<float>::infinity() : wall_distance_m_[i];
  }
  /// Not blocked, and free (or unknown when unknown_cost > 0).
  bool traversable(size_t i) const { return traversable_[i] != 0; }
  /// A free cell with an unknown 4-neighbour (or one on the box's edge).
  bool is_frontier(int c, int r) const;
  /// What a step into cell i costs per metre: the near-wall and the unknown factors.
  double step_factor(size_t i) const { return double(step_factor_[i]); }
  /// Cells whose centres lie in `area` become untraversable (an operator's keep-out area: on the
  /// merged map, in_frame(area, SE2()); in a robot's frame, as the base sent it).
  void forbid(const KeepOutPolygon& area);

 private:
  void classify(const OccupancyGrid& map, int k);
  /// Square dilation of the occupied cells by `cells` (separable: rows, then columns).
  std::vector<uint8_t> dilate_square(int cells) const;
  /// traversable_ and step_factor_ from the layers (read once per neighbour by Dijkstra).
  void summarise();
  /// Per cell, the distance between its centre and the nearest occupied cell's centre when that is
  /// at most `radius_m`, else +inf.
  std::vector<float> wall_distances(double radius_m) const;

  GridPlanningOptions options_;
  Eigen::Vector2d map_origin_m_{0, 0};
  double map_res_ = 0;
  int k_ = 1;                ///< map cells per planning cell, a side
  int col0_ = 0, row0_ = 0;  ///< the map cell of this grid's cell (0, 0)
  int w_ = 0, h_ = 0;
  double res_ = 0;
  std::vector<CellState> cells_;
  std::vector<uint8_t> near_wall_;      ///< square marks (not graded_clearance)
  std::vector<float> wall_distance_m_;  ///< up to the inflation (and graded clearance) radius; or empty
  float inflation_m_ = -1;              ///< blocked within this (-1: only occupied cells)
  std::vector<uint8_t> traversable_;
  std::vector<float> step_factor_;  ///< float: half the memory Dijkstra reads
};

/// Frontier cells in 8-connected pieces, scan order (row by row).
using FrontierPiece = std::vector<Eigen::Vector2i>;
std::vector<FrontierPiece> frontier_pieces(const PlanningGrid& grid);

/// Dijkstra path lengths over traversable cells, 8-connected; a step costs its length times the
/// near-wall and unknown factors of the cell it enters.
struct DistanceField {
  Eigen::Vector2i start{-1, -1};  ///< the cell the search started from; (-1, -1): none
  std::vector<double> length_m;   ///< per cell index; +inf where not reached
  std::vector<int32_t> parent;    ///< per cell index, the previous cell's index; -1 at the start
  /// How far the search got: the largest straight-line distance from the start cell's centre to a
  /// settled cell's (an extent, not a path length: costs do not inflate it).
  double farthest_m = 0;
  bool reached(size_t i) const { return i < length_m.size() && length_m[i] < kUnreached; }
  static constexpr double kUnreached = std::numeric_limits<double>::infinity();
};

/// From `start`; a start that is not traversable starts from nearest_traversable(start,
/// start_search_m) (none: an empty search, start (-1, -1)). With `stop_at`, the search ends once
/// that cell is settled (other lengths are then partial).
DistanceField path_lengths(const PlanningGrid& grid, const Eigen::Vector2i& start, double start_search_m = 0.5,
                           const std::optional<Eigen::Vector2i>& stop_at = std::nullopt);

/// The cell centres from the search's start to `goal`, start first; empty when goal was not reached.
std::vector<Eigen::Vector2d> extract_path_m(const PlanningGrid& grid, const DistanceField& field,
                                            const Eigen::Vector2i& goal);

/// The traversable cell nearest to `cell` (Euclidean) among the cells at most ceil(radius_m /
/// resolution) cells away along each axis (a square window, as the base's exploration always
/// searched), if any.
std::optional<Eigen::Vector2i> nearest_traversable(const PlanningGrid& grid, const Eigen::Vector2i& cell,
                                                   double radius_m);

/// A piece's cell with the shortest path length (the first in piece order on ties); path_m is
/// DistanceField::kUnreached (+inf) when none is reached.
struct PieceReach {
  Eigen::Vector2i cell{-1, -1};
  double path_m = DistanceField::kUnreached;
};
PieceReach nearest_cell_of(const FrontierPiece& piece, const PlanningGrid& grid, const DistanceField& field);

struct NearestFrontierOptions {
  int min_piece_cells = 1;  ///< smaller pieces are noise
  double min_path_m = 0.0;  ///< frontier cells nearer than this along the path are skipped
};
struct FrontierTarget {
  int piece = -1;  ///< index into the pieces given
  Eigen::Vector2i cell{-1, -1};
  Eigen::Vector2d position_m{0, 0};
  double path_m = 0;
};
/// The reached frontier cell with the shortest path, skipping cells for which `skip` (position in
/// metres) is true; nullopt when none is left.
std::optional<FrontierTarget> nearest_frontier(const PlanningGrid& grid, const DistanceField& field,
                                               const std::vector<FrontierPiece>& pieces,
                                               const NearestFrontierOptions& options = {},
                                               const std::function<bool(const Eigen::Vector2d&)>& skip = {});

}  // namespace cairn
