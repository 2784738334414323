#pragma once
// All options of the robot agent's algorithm core, one struct per component, with defaults.
#include "robot_agent/core/dead_reckoning.h"
#include "robot_agent/core/keyframer.h"
#include "robot_agent/core/local_slam.h"
#include "robot_agent/core/objects/object_detector.h"
#include "robot_agent/core/objects/object_tracker.h"
#include "robot_agent/core/objects/optical_flow.h"
#include "robot_agent/core/objects/saliency_projection.h"

namespace cairn::agent {

struct AgentOptions {
  LocalSlamOptions local_slam;
  KeyframerOptions keyframer;
  ObjectDetectorOptions detector;
  ObjectTrackerOptions tracker;
  OpticalFlowOptions optical_flow;  ///< collision risk from monocular flow (Eqs. 1-8)
  /// false: odometry is ignored and the pose is predicted with a constant-velocity model.
  bool use_odometry = true;
  /// A scan waits for odometry with stamp >= its own; beyond this many waiting scans the oldest is
  /// processed anyway (extrapolating the last odometry), so a dead odometry topic cannot stall the
  /// agent. Only reached when odometry is missing or far behind.
  int max_pending_scans = 100;
  /// The laser silent for dead_reckoning.laser_timeout_s while odometry goes on (or a robot without
  /// one): poses from odometry alone, keyframes without scans with odometry-grown covariances, so
  /// that the robot's landmarks and finds still reach the base. false: the agent waits for scans.
  bool dead_reckon_without_laser = true;
  DeadReckoningOptions dead_reckoning;
  bool enable_objects = true;
  /// Beams at least this bright (LaserScan::intensities) hit a teammate's retro-reflective tape:
  /// left out of SLAM and keyframes (teammates move). 0: every beam is used.
  float teammate_min_intensity = 0.9f;
  /// Salient spots of the camera frames go out with the keyframes (Keyframe::salient) for the base's
  /// saliency layer (needs detector.use_saliency).
  bool enable_saliency_map = true;
  /// A teammate's marker seen by the camera (common/robot_markers.h) goes out as a range-bearing
  /// sighting with these sigmas (range: the depth's and the cylinder fit's error grow with range).
  double sighting_sigma_range_m = 0.05;
  double sighting_sigma_range_per_m = 0.01;
  double sighting_sigma_bearing_rad = 0.02;
  SaliencyProjectionOptions saliency_map;
  /// After the agent's loop closing has moved its keyframes, their new poses go out
  /// (AgentOutputs::keyframe_poses) at most this often in mission time, and once more at the end
  /// of input. 0 = after every optimisation.
  double keyframe_poses_min_interval_s = 5.0;
};

}  // namespace cairn::agent
