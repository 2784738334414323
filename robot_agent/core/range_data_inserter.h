#pragma once
// Inserts a scan into a ProbabilityGrid as Cartographer's ProbabilityGridRangeDataInserter2D does
// (Hess et al. 2016, Sec. III-B): endpoint cells get the "hit" odds, cells along each beam the
// "miss" odds, each applied with one lookup in a precomputed table of 32768 entries. An update
// marker ensures a cell is updated at most once per scan (hits win over misses).
#include <Eigen/Core>
#include <cstdint>
#include <vector>

#include "common/se2.h"
#include "robot_agent/core/probability_grid.h"

namespace cairn::agent {

struct RangeDataInserterOptions {
  float hit_probability = 0.55f;
  float miss_probability = 0.49f;
  bool insert_free_space = true;
  double max_ray_length_m = 30.0;  ///< beams are cut to this length (endpoint then not a hit)
  /// Free space is inserted along at most this much of each beam (0: the whole beam). The matchers
  /// read the likelihood field of the hits; free cells only enter the probability scores.
  double max_free_space_length_m = 10.0;
  double field_sigma_cells = 1.0;  ///< hit kernel of the likelihood field
  /// The likelihood field also gets the hit kernel along the segment between consecutive hits
  /// (scan order) closer than this, m (0: hits only). A wall seen at a grazing angle or far away
  /// is sampled by beams metres apart; as dots, a later scan's points on it match only at a few
  /// along-wall shifts (a rippled, biased score along corridors); as a line, anywhere on it.
  double field_line_max_gap_m = 0.0;
  /// ... and only when a neighbouring hit continues the segment's line (within the larger of the
  /// tolerance and ratio x gap): a wall, not a jump between two surfaces.
  bool field_line_collinear = true;
  double field_line_tolerance_m = 0.05;
  double field_line_tolerance_ratio = 0.1;
};

/// Table mapping each value to the value after multiplying the cell's odds by odds(probability),
/// with kUpdateMarker set (Cartographer's ComputeLookupTableToApplyOdds).
std::vector<uint16_t> compute_update_table(float probability);

class RangeDataInserter {
 public:
  explicit RangeDataInserter(const RangeDataInserterOptions& options = {});

  /// `points_sensor`: beam endpoints in the sensor frame; `T_grid_sensor` places the sensor.
  /// The grid grows to fit. Not thread-safe (reuses a scratch buffer).
  void insert(const SE2& T_grid_sensor, const std::vector<Eigen::Vector2f>& points_sensor, ProbabilityGrid* grid) const;

 private:
  void apply(size_t index, const std::vector<uint16_t>& table, ZeroedVector<uint16_t>* cells,
             ZeroedVector<size_t>* touched) const;
  /// Hit kernel along the segments between consecutive hits closer than field_line_max_gap_m.
  void splat_segments(const std::vector<Eigen::Vector2d>& ends, const std::vector<bool>& hit,
                      ProbabilityGrid* grid) const;

  RangeDataInserterOptions options_;
  std::vector<uint16_t> hit_table_;
  std::vector<uint16_t> miss_table_;
  mutable ZeroedVector<size_t> touched_;  ///< scratch: cells updated by the current scan
};

}  // namespace cairn::agent
