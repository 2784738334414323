#pragma once
// The robot agent's algorithm core behind one class (DESIGN.md "Robot agent"): sensor readings in,
// keyframes and object reports out. Single-threaded and deterministic: topics may interleave
// arbitrarily, readings are buffered and processed in stamp order (a scan at t once odometry with
// stamp >= t is present; an RGB-D frame at t once a scan with stamp >= t has been processed), so
// the outputs do not depend on arrival order, as long as odometry runs less than
// dead_reckoning.laser_timeout_s ahead of the laser: beyond, the laser counts as lost (poses from
// odometry alone, agent_pipeline_dead_reckoning.cpp). No clocks, no I/O, no threads.
#include <deque>
#include <optional>
#include <vector>

#include "common/ids.h"
#include "common/keyframe.h"
#include "common/laser_scan.h"
#include "common/object_report.h"
#include "common/sensors.h"
#include "common/trajectory.h"
#include "robot_agent/core/agent_options.h"
#include "robot_agent/core/keyframer.h"
#include "robot_agent/core/local_slam.h"
#include "robot_agent/core/objects/object_detector.h"
#include "robot_agent/core/objects/object_tracker.h"

namespace cairn::agent {

/// A processed scan at its tracked pose in the local frame (what navigation maps and steers by).
struct PosedScan {
  LaserScan scan;  ///< no beams: a pose from odometry alone while the laser is lost
  SE2 T_local_base;
};

struct AgentOutputs {
  std::vector<PosedScan> scans;  ///< every scan processed by this call, in stamp order
  std::vector<Keyframe> keyframes;
  std::vector<ObjectReport> objects;
  /// Every emitted keyframe's pose after the agent's own loop closing, when that moved them
  /// (AgentOptions::keyframe_poses_min_interval_s).
  std::optional<KeyframePoses> keyframe_poses;
  bool empty() const { return keyframes.empty() && objects.empty() && !keyframe_poses; }
};

struct AgentStats {
  int scans_received = 0;
  int scans_matched = 0;  ///< includes the first scan
  int scans_motion_filtered = 0;
  int scans_too_few_points = 0;
  int scans_match_failed = 0;
  int scans_odometry_stalled = 0;  ///< skipped: odometry held its reading while the scan moved
  int scans_out_of_order = 0;      ///< stamp older than the previous scan: dropped
  int scans_without_odometry = 0;  ///< processed without waiting for odometry (see max_pending_scans)
  ScanFilterStats beams;           ///< over all processed scans
  int odometry_received = 0;
  int rgbd_received = 0;
  int rgbd_processed = 0;
  int rgbd_invalid = 0;  ///< size mismatch: skipped
  int detections = 0;
  int keyframes = 0;
  int object_reports = 0;
  int object_tracks = 0;
  int object_tracks_confirmed = 0;
  int submaps_finished = 0;
  int loop_closures = 0;  ///< intra-robot loop-closure constraints found by the local SLAM
  int pose_graph_optimizations = 0;
  float collision_risk = 0.f;      ///< latest optical-flow estimate (0..1), for the status message
  int collision_estimates = 0;     ///< RGB frames that gave a valid flow estimate
  int landmarks_received = 0;      ///< identified landmark (marker) observations
  int robot_sightings = 0;         ///< teammates' markers seen by the camera (also in landmarks_received)
  int landmarks_invalid = 0;       ///< NaN / negative / zero-sigma values: dropped
  int landmarks_in_keyframes = 0;  ///< attached to an emitted keyframe
  int keyframe_pose_updates = 0;   ///< AgentOutputs::keyframe_poses emitted
  int salient_points = 0;          ///< sent with keyframes (Keyframe::salient)
  int teammate_beams = 0;          ///< on a teammate's reflector: left out of SLAM and keyframes
  int laser_losses = 0;            ///< times the laser fell silent while odometry went on
  int laser_recoveries = 0;        ///< ... and came back
  int dead_reckoned_poses = 0;     ///< poses from odometry alone (AgentOptions::dead_reckon_without_laser)
  int keyframes_without_scan = 0;  ///< of `keyframes`, cut from those poses
};

/// A copy of `scan` whose beams at least `min_intensity` bright (a teammate's reflective tape) read
/// "no return", counted in *dropped; the scan itself when min_intensity <= 0 or it has no intensities.
LaserScan without_teammates(const LaserScan& scan, float min_intensity, int* dropped);

class AgentPipeline {
 public:
  AgentPipeline(RobotId robot, const AgentOptions& options = {});

  void add_odometry(const OdometryReading& odometry);
  void add_scan(const LaserScan& scan);
  void add_rgbd(const RgbdFrame& frame);
  /// An identified landmark seen from the base frame at o.stamp_ns. It is attached to the first
  /// keyframe emitted with a stamp >= its own, re-expressed from that keyframe's base frame
  /// (agent_pipeline_landmarks.cpp). Invalid observations are counted and dropped.
  void add_landmark(const LandmarkObservation& observation);

  /// Processes what is ready and returns what was produced since the last call.
  /// `flush`: end of input, process everything buffered.
  AgentOutputs process(bool flush = false);

  AgentStats stats() const;
  /// Every matched scan's pose, in the local frame.
  const Trajectory& trajectory() const { return trajectory_; }
  /// Pose at `stamp_ns` interpolated between processed scans (clamped at the ends).
  SE2 pose_at(StampNs stamp_ns) const;
  const LocalSlam& local_slam() const { return local_slam_; }
  RobotId robot() const { return robot_; }
  /// The laser is silent and poses come from odometry alone (agent_pipeline_dead_reckoning.cpp).
  bool laser_lost() const { return laser_lost_; }
  /// Live input only: whether the stamps may judge the laser lost before its first scan is
  /// processed: once a scan has arrived (stamp order decides from then on), or once none arrived for
  /// laser_timeout_s of arrival (wall) time since the first odometry reading. By stamps alone a scan
  /// that is merely late (its reader matched after the odometry's, a simulator running 25x real
  /// time on a loaded machine) looked lost. Default true: a log is replayed in stamp order.
  void set_stamps_may_judge_laser(bool may) { stamps_may_judge_laser_ = may; }
  const AgentOptions& options() const { return options_; }

 private:
  bool scan_ready(bool flush) const;
  bool rgbd_ready(bool flush) const;
  void process_scan(AgentOutputs* out);
  void process_rgbd(AgentOutputs* out);
  /// A new keyframe out: landmarks, salient spots and (with a scan) the place descriptor attached.
  void emit_keyframe(Keyframe kf, AgentOutputs* out);
  bool dead_reckoning_ready() const;
  void dead_reckoning_step(AgentOutputs* out);
  std::optional<SE2> odometry_at(StampNs stamp_ns) const;
  Anchor anchor_at(StampNs stamp_ns) const;
  void attach_landmarks(Keyframe* kf);
  /// Moves the teammates' markers out of `detections` into landmark observations (sightings);
  /// returns the objects (agent_pipeline_landmarks.cpp).
  std::vector<Detection> take_robot_sightings(StampNs stamp_ns, std::vector<Detection>* detections);
  std::optional<KeyframePoses> keyframe_poses(bool flush);

  RobotId robot_;
  AgentOptions options_;
  LocalSlam local_slam_;
  Keyframer keyframer_;
  ObjectDetector detector_;
  ObjectTracker tracker_;
  OpticalFlowCollision optical_flow_;
  SaliencyPool saliency_pool_;  ///< salient spots seen since the last keyframe

  std::deque<OdometryReading> odometry_;
  std::deque<LaserScan> scans_;
  std::deque<RgbdFrame> frames_;
  std::deque<LandmarkObservation> landmarks_;  ///< waiting for a keyframe at or after their stamp
  bool any_scan_processed_ = false;            ///< or a dead-reckoned pose
  StampNs last_scan_stamp_ns_ = 0;             ///< of the newest processed scan or dead-reckoned pose
  DeadReckoning dead_reckoning_;
  bool laser_lost_ = false;
  bool stamps_may_judge_laser_ = true;  ///< set_stamps_may_judge_laser
  StampNs first_odometry_ns_ = -1;
  StampNs next_dead_reckoning_ns_ = 0;     ///< the next dead-reckoned pose's stamp (laser lost)
  Trajectory trajectory_;                  ///< matched poses
  Trajectory tracked_;                     ///< every processed scan's pose (matched or predicted)
  std::vector<Anchor> anchors_;            ///< emitted keyframes' poses, by seq
  std::deque<Keyframe> recent_keyframes_;  ///< last emitted ones, for the place descriptor
  std::vector<StampNs> anchor_stamps_ns_;
  int optimizations_sent_ = 0;            ///< loop-closing optimisations included in the last keyframe_poses
  std::optional<StampNs> poses_sent_ns_;  ///< last scan stamp when keyframe_poses went out
  std::optional<StampNs> finished_ns_;    ///< last scan stamp of the final optimisation (flush)
  AgentStats stats_;
};

}  // namespace cairn::agent
