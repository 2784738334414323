#pragma once
// Checks of a 2D trajectory against the laser data itself, with no reference: they show whether a
// reference trajectory (a GMapping-corrected log) or an estimate fits the scans better, where the
// ATE between the two cannot say which of them is off.
// - Revisit consistency: scan endpoints placed by the trajectory, each against the nearest endpoint
//   of scans at least `min_index_gap` scans away (a later or earlier pass through the same place).
//   A misplaced pass doubles walls; its endpoints sit centimetres from the other pass's. Blind to
//   what no revisit sees: the heading of a dead-end spur, the length of a corridor driven once.
// - Forward range: where the beams straight ahead hit a flat surface in two consecutive scans and the
//   robot drove straight, the drop in range is the forward motion measured by the laser; the
//   trajectory's forward motion should match it (a stretched map moves further than the laser saw).
// - Affine fit: the ATE after the best 2D affine map from the estimate to the reference, and that
//   map's singular values: a map stretched along one axis shows up as a value away from 1.
#include <Eigen/Core>
#include <vector>

#include "common/carmen_log.h"
#include "common/laser_scan.h"
#include "common/se2.h"
#include "common/trajectory.h"

namespace cairn::slam {

struct RevisitConsistencyOptions {
  int min_index_gap = 20;     ///< scans closer than this in sequence are the same pass
  double radius_m = 0.3;      ///< endpoints with no other-pass endpoint this close are not revisits
  double max_range_m = 20.0;  ///< longer beams are dropped (sparse, grazing)
  double close_m = 0.05;      ///< "within" threshold reported as a fraction
};

struct RevisitConsistency {
  int points = 0;                 ///< endpoints placed
  double revisit_fraction = 0.0;  ///< ... with an other-pass endpoint within radius_m
  double mean_nn_m = 0.0;         ///< over those: mean distance to the nearest other-pass endpoint
  double median_nn_m = 0.0;
  double within_close_fraction = 0.0;
};

/// `scans[i]` taken at `T_world_base[i]` (same length). Throws InputError on mismatched lengths.
RevisitConsistency revisit_consistency(const std::vector<LaserScan>& scans, const std::vector<SE2>& T_world_base,
                                       const RevisitConsistencyOptions& options = {});

struct ForwardRangeOptions {
  int half_width_beams = 1;         ///< beams either side of straight ahead that must agree
  double flatness_fraction = 0.02;  ///< their spread, fraction of the range
  double max_range_m = 49.0;        ///< beyond: no return or too sparse
  double min_range_m = 0.5;
  double max_turn_rad = 1.5 * M_PI / 180.0;  ///< the step must be straight in every trajectory
  double min_motion_m = 0.2;                 ///< laser-measured forward motion below this is skipped
  double max_disagreement_m = 0.3;           ///< a pair where any trajectory disagrees more hit another surface
};

struct ForwardRange {
  int pairs = 0;                             ///< consecutive scan pairs used (the same for every trajectory)
  double laser_forward_m = 0.0;              ///< sum of the range drops
  std::vector<double> trajectory_forward_m;  ///< per trajectory: sum of its forward motions
  std::vector<double> ratio;                 ///< trajectory_forward_m / laser_forward_m
  std::vector<double> median_difference_m;   ///< per trajectory: median of (its forward motion - range drop)
};

/// Uses only the pairs every trajectory in `trajectories` (each the same length as `scans`) accepts.
ForwardRange forward_range(const std::vector<LaserScan>& scans, const std::vector<std::vector<SE2>>& trajectories,
                           const ForwardRangeOptions& options = {});

struct AffineFit {
  double rmse_m = 0.0;                          ///< of reference - (A * estimate + b)
  double scale_major = 1.0, scale_minor = 1.0;  ///< singular values of A
  double major_axis_deg = 0.0;                  ///< reference-frame direction of scale_major
};
/// Least-squares affine map of `estimate` points onto `reference` points (same length, >= 3).
AffineFit affine_fit(const std::vector<Eigen::Vector2d>& estimate, const std::vector<Eigen::Vector2d>& reference);

/// All three for an estimate and the reference it is judged against, over the reference log's
/// scans: `scan_index[k]` is the scan of `reference[k]` in `corrected.scans` (slam_eval.h
/// reference_from_corrected); `estimate` is sampled at reference stamps (sample_at), poses without
/// an estimate are left out of every check.
struct ScanChecks {
  int poses = 0;
  RevisitConsistency reference, estimate;
  ForwardRange forward;  ///< trajectory 0 = reference, 1 = estimate
  AffineFit affine;      ///< estimate onto reference
};
ScanChecks scan_checks(const CarmenLog& corrected, const Trajectory& reference, const std::vector<size_t>& scan_index,
                       const Trajectory& estimate, const RevisitConsistencyOptions& consistency = {},
                       const ForwardRangeOptions& forward = {});

}  // namespace cairn::slam
