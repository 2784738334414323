#pragma once
// Scores a merged mission against the simulator's ground truth: per-robot trajectory error of the
// base station's global keyframe poses, and objects found (recall, precision, position error) per
// class. Inputs are the files the simulator and the base station write; see docs/architecture.md.
#include <nlohmann/json.hpp>

#include <optional>
#include <string>
#include <vector>

#include "common/ids.h"
#include "common/trajectory.h"
#include "tools/eval/coverage_eval.h"

namespace cairn::eval {

struct EvalOptions {
  double object_match_distance_m = 1.0;  ///< a detection within this (xy) of a same-class truth matches
};

struct ObjectScore {
  std::string class_name;  ///< "all" for the total
  int ground_truth = 0;
  int detected = 0;
  int matched = 0;
  double mean_error_xy_m = 0, max_error_xy_m = 0, mean_error_xyz_m = 0;
  int objects_found = 0;  ///< robot-frame scores only: objects matched by at least one report
  double recall() const { return ground_truth ? double(matched) / ground_truth : 0.0; }
  double precision() const { return detected ? double(matched) / detected : 0.0; }
};

struct RobotScore {
  RobotId robot;
  int keyframes = 0;
  std::optional<TrajectoryErrorStats> global;   ///< in the world frame, no alignment
  std::optional<TrajectoryErrorStats> aligned;  ///< after a best SE2 alignment
};

/// Objects scored in the robots' own frames (objects_robot_frame.csv from the base, each robot's
/// true start from gt_robots.csv): the object pipeline without the robots' placement error at the
/// base. Every report is scored on its own (duplicates across robots are expected): precision =
/// reports within the match distance of a same-class object / reports; recall = objects found by at
/// least one report; the error is each matched report's distance to its nearest object.
struct RobotFrameScore {
  std::string placement;  ///< "true start" (local SLAM + true start) or "true anchor" (true anchor pose)
  std::vector<ObjectScore> classes;
  ObjectScore objects;
};

/// Every placed robot's keyframes aligned to the truth by ONE rigid transform: how consistent the
/// merged map is in itself. The robots' global error is this plus where the anchor (the first
/// robot's known start) put the whole map: a small heading error there turns it about the entry.
struct MapConsistency {
  int robots = 0, keyframes = 0;
  double ate_rmse_m = 0, ate_max_m = 0;
  double rotation_deg = 0, shift_m = 0;  ///< the transform that best aligns the map to the world
  SE2 T_world_map;                       ///< that transform
};

struct MissionScore {
  std::vector<RobotScore> robots;
  std::optional<MapConsistency> map_consistency;  ///< nullopt when fewer than 2 keyframes are placed
  std::vector<ObjectScore> classes;
  ObjectScore objects;  ///< all classes together
  /// Objects reported only in a robot's own frame (never placed on the map): not scored above.
  int unplaced_objects = 0;
  std::vector<RobotFrameScore> robot_frame;  ///< empty when objects_robot_frame.csv is absent
  std::optional<CoverageScore> coverage;     ///< of the explorable area (coverage_eval.h)
};

/// Reads gt_robot<N>.csv / gt_objects.csv from `ground_truth_dir` and trajectory_robot<N>.csv /
/// objects.csv from `results_dir`. Throws InputError naming a missing or malformed file.
MissionScore evaluate_mission(const std::string& ground_truth_dir, const std::string& results_dir,
                              const EvalOptions& options = {});

nlohmann::json to_json(const MissionScore& score);
/// A few human-readable lines for the terminal.
std::string format_score(const MissionScore& score);

}  // namespace cairn::eval
