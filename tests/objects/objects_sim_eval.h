#pragma once
// Core-level evaluation of the object pipeline in a simulated world, without DDS: the sim core
// renders every robot's sensors, one AgentPipeline per robot consumes them, the latest report of
// each object is placed in the world through its anchor keyframe and the robot's true start pose
// (T_world_object = T_world_start * T_local_anchor * T_anchor_object, Eqs. 20-21), reports of the
// same class closer than merge_distance_m are merged (as the base does), and the result is scored
// against the world's objects like tools/eval: same class within match_distance_m (xy).
#include <string>
#include <vector>

#include "robot_agent/core/agent_options.h"

namespace cairn::agent {

struct ClassScore {
  std::string class_name;  ///< "all" for the total
  int ground_truth = 0, detected = 0, matched = 0;
  double mean_error_xy_m = 0.0, max_error_xy_m = 0.0, mean_error_xyz_m = 0.0;
  double recall() const { return ground_truth ? double(matched) / ground_truth : 0.0; }
  double precision() const { return detected ? double(matched) / detected : 0.0; }
};

struct SimEvalOptions {
  double match_distance_m = 1.0;
  double merge_distance_m = 0.8;
  double max_sim_s = -1.0;  ///< < 0: the world's duration
  std::string routes_yaml;  ///< the robots' scripted routes (worlds/routes/*.yaml); empty: the world file's
  AgentOptions agent;
};

struct SimEvalResult {
  std::vector<ClassScore> classes;  ///< per class, then "all" last
  /// The same reports placed through the TRUE pose of their anchor keyframe (T_world_base at the
  /// keyframe's stamp) instead of the robot's local SLAM pose: the object pipeline's own error,
  /// without the SLAM drift of the anchor.
  std::vector<ClassScore> classes_true_anchor;
  int frames = 0, reports = 0;
  double wall_ms_per_frame = 0.0;   ///< detection + tracking + SLAM, whole AgentPipeline::process
  std::vector<std::string> placed;  ///< one line per report placed in the world (for diagnosis)
  std::string summary() const;
};

SimEvalResult evaluate_objects_in_world(const std::string& world_yaml, const SimEvalOptions& options = {});

/// Per-detection error of the detector alone: every frame's detections are placed in the world with
/// the robot's TRUE pose at the frame stamp and compared with the nearest same-class object (within
/// match_distance_m). The error is split along the horizontal viewing ray (+: beyond the true
/// centre, away from the camera) and across it, per object (so the cause of a bias is visible);
/// the means and RMS are over the detections with depth (not the ground-homography fallback).
struct DetectionBias {
  int object_id = -1;
  std::string class_name, shape;
  int detections = 0, truncated = 0, without_depth = 0;
  double mean_along_ray_m = 0.0, mean_across_ray_m = 0.0, rms_xy_m = 0.0, mean_range_m = 0.0;
  std::vector<std::string> lines;  ///< one per detection: robot, stamp, error, flags, fitted shape
};
std::vector<DetectionBias> diagnose_detections_in_world(const std::string& world_yaml,
                                                        const SimEvalOptions& options = {});
std::string format_bias(const std::vector<DetectionBias>& bias);

}  // namespace cairn::agent
