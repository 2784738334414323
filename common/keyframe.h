#pragma once
// A keyframe as the robot agent emits it and the base station consumes it (the DDS `Keyframe`
// message mirrors this; dds/ converts). Poses are in the robot's own local map frame, whose origin
// is where that robot started: the base station does not know how these frames relate.
#include <vector>

#include "common/ids.h"
#include "common/landmark_observation.h"
#include "common/laser_scan.h"
#include "common/se2.h"
#include "common/time.h"

namespace cairn {

/// A salient spot the robot's camera saw (robot_agent/core/objects/saliency_projection.h): where a
/// colourful, salient surface stands on the floor plane, from a keyframe's base frame, and how
/// salient it is (0..1). The base draws them into the saliency layer that weights frontiers.
struct SalientPoint {
  float x_m = 0.f, y_m = 0.f;
  float weight = 0.f;
};

struct Keyframe {
  KeyframeId id;
  StampNs stamp_ns = 0;
  SE2 T_local_base;  ///< pose in the robot's local frame
  Covariance3 covariance = Covariance3::Identity() * 1e-4;
  /// Relative pose from the previous keyframe (seq-1) to this one, as local SLAM measured it.
  /// Unused for seq 0.
  SE2 T_prev_this;
  Covariance3 edge_covariance = Covariance3::Identity() * 1e-4;
  LaserScan scan;                       ///< in the base frame (laser at origin)
  std::vector<float> place_descriptor;  ///< rotation-invariant, may be empty
  /// Identified landmarks (markers) seen around this keyframe, expressed from its base frame.
  std::vector<LandmarkObservation> landmarks;
  /// Salient spots seen by the camera since the previous keyframe, from this keyframe's base frame.
  std::vector<SalientPoint> salient;
};

/// The agent's latest estimate of its keyframes' poses, after its own loop closures (the DDS
/// `KeyframePoses` message mirrors this). Same local frame as Keyframe::T_local_base (the agent's
/// loop closing keeps its first pose fixed), better than the front-end poses the keyframes carry.
/// The base takes the relative poses between consecutive keyframes from it.
struct KeyframePose {
  int32_t seq = 0;
  SE2 T_local_base;
};
struct KeyframePoses {
  RobotId robot;
  StampNs stamp_ns = 0;             ///< of the latest scan the estimate includes
  std::vector<KeyframePose> poses;  ///< ascending seq
};

}  // namespace cairn
