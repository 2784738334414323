#pragma once
// Identified landmarks (markers) at the base station: each robot's estimate of every landmark it saw
// in its own local frame, and the rigid transform between two robots' frames from the landmarks
// both saw (least squares, Umeyama 1991 without scale, with the worst landmark dropped while the
// residual is above a gate: a mis-identified marker must not produce a wrong merge).
// The MultiRobotMapper uses these to offer marker-based link hypotheses and to add landmark nodes
// with range-bearing residuals to its pose graph (robot_linker_landmarks.cpp, multi_robot_mapper_graph.cpp).
#include <Eigen/Core>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "common/ids.h"
#include "common/keyframe.h"
#include "common/landmark_observation.h"
#include "common/se2.h"

namespace cairn::base {

struct LandmarkOptions {
  bool enabled = true;        ///< landmark nodes in the graph and marker-based links
  double min_range_m = 0.05;  ///< closer observations are ignored (bearing undefined)
  /// The graph uses the observations' sigmas times this. Many detections of few markers, each an
  /// independent residual, against conservative keyframe edges: unscaled, the markers' noise bends
  /// the trajectories (simulated corridor, tools/mrlog/mrlog_replay_test.cpp: trajectory max error
  /// 0.40 m at 1x, 0.24 m at 3x, 0.12 m at 6x, 0.08 m at 10x; scans-only 0.08 m), and repeated
  /// detections share errors (detector bias, stamp offsets) that independent residuals over-count.
  double sigma_scale = 10.0;
  /// Distinct landmarks both robots saw needed to link them on markers when the map check is
  /// inconclusive (featureless or unseen overlap), and when it positively confirms the hypothesis.
  int min_link_landmarks = 3;
  int min_link_landmarks_map_confirmed = 2;
  double max_link_rms_m = 0.35;    ///< RMS of the aligned landmark positions
  double min_link_spread_m = 1.5;  ///< the shared landmarks span at least this (rotation accuracy)
  /// The closure that places a robot linked on markers or sightings: it gives the solver the robot's
  /// first placement and the graph its connection, and the landmark and sighting residuals and the
  /// scan closures then do the work. Wide, because it keeps the link-time alignment of a few early
  /// points: at 0.5 m / 0.2 rad one 0.57 m off outweighed the anchor robot's chain of keyframe edges
  /// and turned the whole demo map 1.6 deg about its start (every robot 0.53-0.75 m RMSE; wide,
  /// 0.05-0.07 m).
  double link_sigma_xy_m = 5.0;
  double link_sigma_yaw_rad = 2.0;
  /// Sightings of teammates (sightings.h) in the graph: the observation's sigmas times this (a few
  /// detections per second of one robot share their errors), and the seen robot's interpolated
  /// position with this sigma, expressed from a keyframe at least sighting_min_offset_m away.
  double sighting_sigma_scale = 10.0;
  double sighting_interpolation_sigma_m = 0.03;
  double sighting_min_offset_m = 0.1;
  /// A pair refuted or deferred is judged again after this many new observations of either robot.
  int retry_observations = 10;
};

/// One robot's estimate of a landmark in its local frame.
struct LocalLandmark {
  Eigen::Vector2d sum_m = Eigen::Vector2d::Zero();  ///< sum of observed points (local frame)
  int observations = 0;
  KeyframeId nearest;  ///< keyframe with the closest observation
  double nearest_range_m = 1e300;
  Eigen::Vector2d position_m() const { return observations > 0 ? Eigen::Vector2d(sum_m / observations) : sum_m; }
};
using LocalLandmarks = std::map<LandmarkId, LocalLandmark>;

/// Adds a keyframe's valid observations (range >= min_range_m) to its robot's local estimates.
/// Returns how many were used; `invalid` (may be null) gets how many were dropped.
int accumulate_landmarks(const Keyframe& kf, double min_range_m, LocalLandmarks* landmarks, int* invalid);

struct LandmarkAlignment {
  bool ok = false;
  SE2 T_a_b;                        ///< maps robot b's local frame into robot a's
  std::vector<LandmarkId> used;     ///< shared landmarks kept by the alignment
  std::vector<LandmarkId> dropped;  ///< shared landmarks dropped as outliers
  double rms_m = 0.0;
  double spread_m = 0.0;  ///< largest distance between two used landmarks
  std::string reason;     ///< why not ok
};

/// Aligns the landmarks both `a` and `b` saw (see the file comment); ok when at least `min_landmarks`
/// remain with RMS <= max_rms_m and spread >= min_spread_m.
LandmarkAlignment align_landmarks(const LocalLandmarks& a, const LocalLandmarks& b, int min_landmarks, double max_rms_m,
                                  double min_spread_m);

/// Number of landmark ids present in both.
int shared_landmarks(const LocalLandmarks& a, const LocalLandmarks& b);

/// printf-formats one number (for the reasons in link decisions).
std::string format_number(const char* format, double value);
/// How far placement `b` lies from `a`: "0.51 m and 4.9 deg" (for the same reasons).
std::string format_offset(const SE2& a, const SE2& b);

}  // namespace cairn::base
