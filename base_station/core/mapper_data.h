#pragma once
// MapperData: what the base station's merger knows, as plain data (Cartographer's PoseGraphData).
// MultiRobotMapper stores into it (ingest) and writes the optimised poses; RobotLinker decides on
// it (the anchor, which robots are placed where, accepted loop closures, unlinked robots' own-frame
// solutions). The helpers below only derive poses from it: they decide nothing.
// Frames: each robot's keyframes are in its own local frame (T_local_base); a linked robot's local
// frame sits at T_global_local (its "correction") in the global frame of the anchor robot.
#include <Eigen/Core>
#include <map>
#include <optional>
#include <vector>

#include "base_station/core/keyframe_pose_graph.h"
#include "base_station/core/landmarks.h"
#include "base_station/core/mapper_options.h"
#include "base_station/core/pcm.h"
#include "base_station/core/sightings.h"
#include "common/keyframe.h"
#include "common/object_report.h"
#include "common/trajectory.h"

namespace cairn::base {

using KeyframeMap = std::map<KeyframeId, Keyframe>;

/// One robot's keyframes in seq order: a range over MapperData::keyframes.
class RobotKeyframes {
 public:
  RobotKeyframes(KeyframeMap::const_iterator begin, KeyframeMap::const_iterator end) : begin_(begin), end_(end) {}
  KeyframeMap::const_iterator begin() const { return begin_; }
  KeyframeMap::const_iterator end() const { return end_; }
  bool empty() const { return begin_ == end_; }

 private:
  KeyframeMap::const_iterator begin_, end_;
};

/// An unlinked robot's own-frame solution: its keyframes, front-end edges and its own accepted loop
/// closures, solved with its first keyframe held (RobotLinker).
struct OwnFrame {
  size_t loops = 0;  ///< intra-robot loop closures in that solve
  std::map<KeyframeId, SE2> poses;
};

/// Roughly where a robot entered, as the team knows it (the same door, a few metres apart): a
/// prior that bounds the link search, never a link by itself (RobotLinker).
struct EntryHint {
  SE2 T_global_local;  ///< the robot's local frame (where it entered) in the global frame
  double sigma_xy_m = 1.0;
  double sigma_yaw_rad = 0.2;
  /// Chi-square of a placement of the robot's local frame against the hint (error at the entry),
  /// with other variances (another robot's hint) added to the hint's.
  double chi2(const SE2& placed_T_global_local, double extra_var_xy_m2 = 0.0, double extra_var_yaw_rad2 = 0.0) const {
    const SE2 E = T_global_local.between(placed_T_global_local);
    return E.translation().squaredNorm() / (sigma_xy_m * sigma_xy_m + extra_var_xy_m2) +
           E.yaw() * E.yaw() / (sigma_yaw_rad * sigma_yaw_rad + extra_var_yaw_rad2);
  }
};

struct MapperData {
  KeyframeMap keyframes;
  std::map<ObjectId, ObjectReport> reports;
  std::map<KeyframeId, SE2> agent_poses;              ///< the agents' loop-closed local poses (add_keyframe_poses)
  std::map<RobotId, SE2> hints;                       ///< set_robot_start: T_global_local pinned by a prior
  std::map<RobotId, SE2> starts;                      ///< linked robots: initial T_global_local
  std::map<RobotId, EntryHint> entry_hints;           ///< set_entry_hint: uncertain starts, never a link alone
  std::optional<RobotId> anchor;                      ///< the robot whose local frame is the global frame
  std::map<KeyframeId, SE2> optimized;                ///< global poses from the last solve
  std::vector<LoopClosure> loops;                     ///< accepted loop closures (intra and inter-robot), a = older
  std::map<RobotId, OwnFrame> own_frames;             ///< unlinked robots with intra-robot loop closures
  std::map<RobotId, LocalLandmarks> local_landmarks;  ///< each robot's landmarks in its local frame
  std::vector<Sighting> sightings;                    ///< robots seeing robots, in arrival order
  StampNs latest_stamp_ns = 0;                        ///< newest keyframe stamp of any robot: mission time
  /// Mission time at which each robot was linked (its first keyframe's for the anchor and hinted ones).
  std::map<RobotId, StampNs> linked_at_ns;

  bool linked(RobotId robot) const { return starts.count(robot) > 0; }
  /// A stored keyframe (checked: asking for one that is not stored is a bug).
  const Keyframe& keyframe(KeyframeId id) const;
  RobotKeyframes robot_keyframes(RobotId robot) const;
  /// Object reports whose anchor keyframe has not arrived yet.
  std::vector<ObjectId> pending_objects() const;
  /// The robots with stored keyframes, by id.
  std::vector<RobotId> keyframe_robots() const;
  /// T_global_local of a linked robot from its latest optimised keyframe (its start before any).
  SE2 correction(RobotId robot) const;
  /// nullopt when the keyframe is unknown or its robot is not linked.
  std::optional<SE2> global_pose(KeyframeId id) const;
  /// Keyframe poses in the global frame, by seq; empty when the robot is not linked.
  Trajectory global_trajectory(RobotId robot) const;
  /// The keyframe's pose as its agent last estimated it (add_keyframe_poses); keyframes newer than
  /// that estimate carried by the front end from the latest one it covers; the front end's pose
  /// when the agent sent none.
  SE2 agent_local_pose(KeyframeId id) const;
  /// The keyframe's pose in its robot's local frame as refined by the base: a linked robot's global
  /// pose taken back to its local frame; an unlinked robot's own-frame solution, later keyframes
  /// carried by the front end. Link hypotheses are judged by these poses: the front end's drift
  /// (0.29 m ATE over the middle third of MIT CSAIL) would go into a link's transform.
  SE2 refined_local_pose(KeyframeId id) const;
  /// A keyframe's pose in frame A of a link judged from ra: global when ra is placed, else ra's
  /// refined local pose.
  SE2 pose_in_frame_a(RobotId ra, KeyframeId id) const {
    return linked(ra) ? *global_pose(id) : refined_local_pose(id);
  }
};

/// Information of a measured edge; nullopt when the covariance is not positive definite.
std::optional<Eigen::Matrix3d> information_of(const Covariance3& covariance);
Eigen::Matrix3d diag_information(double sigma_xy_m, double sigma_yaw_rad);

/// The odometry edge from prev to kf: the front end's measured edge (the agent's loop-closed poses
/// when it sent them), or (seq gap, or no valid covariance; *gap set) their local poses' difference
/// with the gap uncertainty of MapperOptions.
PoseGraphEdge chain_edge(const MapperData& data, const Keyframe& prev, const Keyframe& kf, const MapperOptions& options,
                         bool* gap);

}  // namespace cairn::base
