#pragma once
// MultiRobotMapper: the base station's merger. It stores every robot's keyframes (odometry chains
// in each robot's local frame) and object reports, places linked robots in the global frame with a
// Ceres SE2 pose graph (DESIGN.md "Base station" 1, 4, 5), and derives the global occupancy grid and
// the merged objects in global coordinates.
// Robots start at unknown relative poses. The first robot seen (the lowest id before the first
// optimize()) anchors the global frame; set_robot_start is an optional hint that links a robot
// directly. Other robots get linked by verified inter-robot loop closures: Scan Context candidates,
// scan-matching verification, then PCM (maximum clique) over each robot pair's closures before
// the pair is first linked (a wrong merge is worse than a late one), and a Cauchy loss on every
// loop edge afterwards. On a new link the graph is re-solved from a LAGO initialisation; other
// updates are incremental and warm-started. Unlinked robots' data is kept but not placed.
// Single-threaded and deterministic; queries rebuild cached results lazily, so even const methods
// must not be called concurrently (the console works on snapshots, see console/snapshot.h).
#include <map>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "base_station/core/global_map_renderer.h"
#include "base_station/core/global_object.h"
#include "base_station/core/map_consistency.h"
#include "base_station/core/mapper_options.h"
#include "base_station/core/pose_graph_2d.h"
#include "common/keyframe.h"
#include "common/object_report.h"
#include "common/occupancy_grid.h"
#include "common/trajectory.h"

namespace cairn::base {

enum class AddStatus {
  kAccepted,   ///< stored and usable
  kPending,    ///< stored, waits for something else (e.g. an object's anchor keyframe)
  kDuplicate,  ///< already stored (or an older version of it): nothing changed
  kRejected,   ///< invalid input: nothing changed
};
const char* to_string(AddStatus status);

struct AddResult {
  AddStatus status = AddStatus::kRejected;
  std::string reason;  ///< why it was rejected / pending, or notes (e.g. dropped NaN points)
  bool stored() const { return status == AddStatus::kAccepted || status == AddStatus::kPending; }
};

/// One decision on a link hypothesis (a PCM clique between two robots, or a closure that would move
/// a linked pair), for the app's log: "robot 1 linked to robot 0 via 4 closures" or the reason.
struct LinkEvent {
  RobotId robot;  ///< the robot being linked (or whose closure was judged)
  RobotId other;
  int closures = 0;  ///< closures of the hypothesis
  bool accepted = false;
  bool inconclusive = false;         ///< too little overlap to judge: candidates kept, judged again later
  double contradiction_ratio = 0.0;  ///< map check (0 when not run)
  std::string reason;                ///< why rejected / deferred, or "linked"
  std::vector<LoopClosure> members;  ///< the judged closures (a link hypothesis' clique)
  /// Closures found around the hypothesis by the guided search (MapperOptions::guided_link), a on
  /// the placed side, when the link was accepted as they place the robot (empty otherwise).
  std::vector<LoopClosure> guided;
  /// The map check of the rigid placement when the guided search then ran (-1: it did not run).
  double rigid_contradiction_ratio = -1.0;
};

/// The pose-graph edge of a loop closure: its covariance inverted (identity if not positive definite).
PoseGraphEdge loop_edge(const LoopClosure& c);
/// The same closure seen from b (a and b swapped, transform inverted, covariance rotated into b).
LoopClosure reversed(const LoopClosure& c);

/// Counters of link decisions since construction.
struct LinkStats {
  int hypotheses = 0;  ///< cliques of at least min_link_clique judged
  int linked = 0;
  int rejected_map_contradiction = 0;  ///< cliques refuted by the map check (closures dropped)
  int deferred_spread = 0;             ///< cliques whose closures cover too little of a trajectory
  int deferred_inconclusive = 0;       ///< cliques whose maps overlap too little to be checked
  int link_members_held = 0;           ///< members of accepted cliques off their common fit: held for the map check
  int linked_pair_closures = 0;        ///< inter-robot closures into already linked pairs
  int linked_pair_implausible = 0;     ///< of those, disagreeing beyond any drift: dropped unchecked
  int linked_pair_checked = 0;         ///< of those, disagreeing with the estimate: map-checked
  int linked_pair_rejected = 0;        ///< of those, refuted and dropped
  int intra_closures = 0;              ///< verified closures within one robot's trajectory
  int intra_rejected = 0;              ///< of those, contradicting the robot's own map beyond its drift
};

struct OptimizeResult {
  PoseGraphSolveResult solve;
  int nodes = 0;
  int edges = 0;
  int priors = 0;
  int gap_edges = 0;  ///< chains bridged by local poses because a keyframe is missing
  int unlinked_robots = 0;
  int loop_closures = 0;  ///< accepted loop edges in the graph (intra + inter-robot)
  int inter_robot_closures = 0;
  int pending_candidates = 0;         ///< verified inter-robot closures waiting for PCM
  std::vector<RobotId> newly_linked;  ///< robots linked by this call
  bool full_resolve = false;          ///< LAGO initialisation + full solve happened
  /// The whole graph was solved (link, or refinement after loop closures); otherwise only the
  /// window of new keyframes / new loop edges (solve.variable_blocks nodes) moved.
  bool full_solve = false;
  std::vector<LinkEvent> link_events;  ///< link decisions of this call (deduplicated per pair)
  int object_edges = 0;                ///< object observations in the graph (object_constraints.h)
  int constrained_objects = 0;         ///< merged objects with observations in the graph
};

struct RobotSummary {
  RobotId id;
  bool linked = false;
  int keyframes = 0;
  int objects = 0;  ///< reports from this robot (placed or pending)
  StampNs last_stamp_ns = 0;
  int32_t last_seq = -1;
  int missing_keyframes = 0;  ///< gaps in seq 0..last_seq
  /// Correction global <- robot local frame (identity when not linked); the "correction" topic.
  SE2 T_global_local;
  bool anchor = false;           ///< this robot's frame is the global frame's reference
  int inter_robot_closures = 0;  ///< accepted closures touching this robot and another
};

class MultiRobotMapper {
 public:
  explicit MultiRobotMapper(const MapperOptions& options = {});

  /// Links a robot: its local frame sits at T_global_local in the global frame.
  void set_robot_start(RobotId robot, const SE2& T_global_local);
  AddResult add_keyframe(const Keyframe& keyframe);
  /// The agent's loop-closed estimate of its keyframes (common/keyframe.h): from the next
  /// optimize() the chain between consecutive keyframes follows it instead of the front end's
  /// edges, for the robot's own-frame solution, the intra-robot gate and the global graph (edges
  /// re-measured in place, then a full warm-started solve). It replaces the robot's previous one;
  /// poses of keyframes not received yet are kept for when they arrive. Rejected whole (nothing
  /// changes) when a pose is not finite, a seq is negative or repeated.
  AddResult add_keyframe_poses(const KeyframePoses& update);
  AddResult add_object(const ObjectReport& report);
  /// Rebuilds the pose graph of all linked robots (warm-started from the last solution) and solves.
  OptimizeResult optimize();

  std::vector<RobotSummary> robots() const;
  bool linked(RobotId robot) const { return starts_.count(robot) > 0; }
  /// Keyframe poses in the global frame, by seq; empty when the robot is not linked.
  Trajectory global_trajectory(RobotId robot) const;
  /// nullopt when the keyframe is unknown or its robot is not linked.
  std::optional<SE2> global_pose(KeyframeId id) const;
  /// A stored keyframe's pose in its robot's local frame as refined by the base: a linked robot's
  /// global pose taken back to its local frame; an unlinked robot's own-frame solution (its
  /// keyframes, front-end edges and its own accepted loop closures, solved at optimize()), later
  /// keyframes carried by the front end. Link hypotheses are judged by these poses: the front end's
  /// drift (0.29 m ATE over the middle third of MIT CSAIL) would go into the clique's transform
  /// and the map check.
  SE2 refined_local_pose(KeyframeId id) const;
  /// A stored keyframe's pose as its agent last estimated it (add_keyframe_poses); keyframes newer
  /// than that estimate carried by the front end from the latest one it covers; the front end's pose
  /// when the agent sent none.
  SE2 agent_local_pose(KeyframeId id) const;
  const std::map<KeyframeId, Keyframe>& keyframes() const { return keyframes_; }
  const std::map<ObjectId, ObjectReport>& object_reports() const { return reports_; }
  /// Reports whose anchor keyframe has not arrived yet.
  std::vector<ObjectId> pending_objects() const;
  /// Merged objects of linked robots, sorted by id.
  std::vector<GlobalObject> objects() const;
  /// Occupancy grid of every linked keyframe's scan at its current global pose.
  const OccupancyGrid& global_map() const;
  double mapped_area_m2() const { return global_map().known_area_m2(); }
  /// The pose graph as last optimised (for export).
  const PoseGraph2d& graph() const { return graph_; }
  const MapperOptions& options() const { return options_; }
  /// Accepted loop closures (intra- and inter-robot), a = older keyframe.
  const std::vector<LoopClosure>& loop_closures() const { return loops_; }
  const LoopCloserStats& loop_closer_stats() const { return loop_closer_.stats(); }
  const LinkStats& link_stats() const { return link_stats_; }
  // Landmarks (multi_robot_mapper_landmarks.cpp).
  /// Optimised global positions of the landmarks seen by linked robots.
  std::map<LandmarkId, Eigen::Vector2d> landmarks() const { return graph_.landmark_estimates(); }
  /// Marker-based link decisions so far (accepted ones and the latest refusal per pair).
  const std::vector<LinkEvent>& landmark_link_events() const { return landmark_link_events_; }
  /// Each robot's own estimate of the landmarks it saw, in its local frame.
  const std::map<RobotId, LocalLandmarks>& local_landmarks() const { return local_landmarks_; }
  // Objects as graph constraints (multi_robot_mapper_objects.cpp).
  /// The object observations of the last optimize() (each report of a verified merged object).
  const std::vector<ObjectConstraint>& object_observations() const { return object_constraints_; }

  /// True while the last loop closures have not been solved to convergence over the whole graph
  /// (each optimize() without new keyframes runs incremental_max_iterations more, one with new
  /// keyframes at most every MapperOptions::refine_every_updates): call optimize() until false
  /// before exporting a final map.
  bool refinement_pending() const { return refine_pending_; }
  /// Bumped whenever any global pose or object may have changed.
  uint64_t version() const { return version_; }

 private:
  SE2 start_of(RobotId robot) const { return starts_.at(robot); }
  /// Current T_global_local of a linked robot from its latest optimised keyframe.
  SE2 correction(RobotId robot) const;
  void add_robot_chain(RobotId robot, OptimizeResult* result);
  /// The odometry edge from prev to kf: the front end's measured edge, or (seq gap or no valid
  /// covariance; *gap set) their local poses' difference with the gap uncertainty.
  PoseGraphEdge chain_edge(const Keyframe& prev, const Keyframe& kf, bool* gap) const;
  std::vector<GlobalObject> compute_objects() const;
  // Automatic linking (multi_robot_mapper_linking.cpp).
  void choose_anchor();
  void detect_new_loops(OptimizeResult* result);
  void link_robot_pairs(OptimizeResult* result);
  /// PCM clique -> spread -> map check for one unlinked pair; true when the pair got linked.
  bool try_link_pair(RobotId ra, RobotId rb, std::vector<LoopClosure>* candidates, OptimizeResult* result);
  void place_new_robots();
  /// Re-solves the own-frame graph of each unlinked robot whose accepted intra-robot loop closures
  /// changed (multi_robot_mapper_linking.cpp).
  void refresh_own_frames();

  RobotId component_of(RobotId robot) const;
  void update_graph(OptimizeResult* result);
  void add_loop_edges();
  // Landmarks (multi_robot_mapper_landmarks.cpp).
  /// Stores kf's observations in its robot's local landmarks and tries marker-based links.
  void note_landmarks(const Keyframe& kf);
  /// Links ra and rb on shared landmarks when the alignment and the map check allow; true if linked.
  bool try_link_by_landmarks(RobotId ra, RobotId rb);
  /// Range-bearing edges of the robot's keyframes in the graph that have none yet.
  void add_landmark_edges(RobotId robot);
  // Objects as graph constraints (multi_robot_mapper_objects.cpp).
  /// Recomputes the object observations from the current merge; sets rebuild_graph_ when an
  /// observation already in the graph changed or went away.
  void refresh_object_constraints();
  /// Adds the object observations whose anchor is in the graph and that are not in it yet.
  void add_object_edges();
  // Link hypothesis checks (multi_robot_mapper_checks.cpp).
  /// Why the clique `closures` (a = ra, b = rb) covers too little of a trajectory; empty if not.
  std::string spread_deficit(const std::vector<LoopClosure>& closures) const;
  /// The clique's link as T_A_blocal (A: the global frame when ra is placed, else ra's local
  /// frame): the best rigid fit of both keyframes of every closure when either side's span
  /// min_link_spread_m, else the mean of the closures' transforms.
  SE2 link_hypothesis(RobotId ra, const std::vector<LoopClosure>& closures) const;
  /// Map check of the clique as a link of rb to ra (accepted, or the reason): rb placed rigidly by
  /// the clique; if that is refuted by a near miss (GuidedLinkOptions::max_rigid_contradiction_ratio),
  /// or always with GuidedLinkOptions::on_every_link, placed by the clique and the guided search's
  /// closures (ev.guided), whose verdict then counts only if it accepts (on_every_link: always).
  LinkEvent judge_link(RobotId ra, RobotId rb, const std::vector<LoopClosure>& closures) const;
  /// A keyframe's pose in frame A of a link judged from ra: global when ra is placed, else ra's
  /// refined local pose.
  SE2 pose_in_frame_a(RobotId ra, KeyframeId id) const {
    return linked(ra) ? *global_pose(id) : refined_local_pose(id);
  }
  // Guided search around a link hypothesis (multi_robot_mapper_guided.cpp).
  /// Frame A's keyframes with their poses there: every linked robot's (global) when ra is linked,
  /// else ra's own (refined local poses).
  std::vector<std::pair<KeyframeId, SE2>> placed_side(RobotId ra) const;
  /// Verified closures (a in frame A, b = rb) between rb's keyframes placed by T_A_blocal and the
  /// nearest keyframes of frame A, each searched in a small window around the hypothesis.
  std::vector<LoopClosure> guided_closures(RobotId ra, RobotId rb, const SE2& T_A_blocal) const;
  /// rb's keyframes in frame A solved against the clique and the guided closures (a in frame A,
  /// held fixed; they fix the gauge), starting from T_A_blocal and keeping rb's own map as stiff as
  /// its front end's uncertainty says (best effort: the solve's convergence is not checked). Guided closures the
  /// solution leaves off by more than GuidedLinkOptions::max_residual_* are dropped from *guided, and the rest solved
  /// again.
  PlacedScans tentative_placement(RobotId ra, RobotId rb, const SE2& T_A_blocal, const std::vector<LoopClosure>& clique,
                                  std::vector<LoopClosure>* guided) const;
  /// How far closure c (a = ra) is off the link T_A_blocal, in units of the linked-pair gate
  /// (at most 1: within it in translation and yaw).
  double link_misfit(RobotId ra, const SE2& T_A_blocal, const LoopClosure& c) const;
  /// Whether an inter-robot closure between two robots of one component may join the graph.
  bool accept_linked_pair_closure(const LoopClosure& c, OptimizeResult* result);
  /// Whether a closure within one robot agrees with its own local poses up to its possible drift.
  bool accept_intra_robot_closure(const LoopClosure& c);
  /// Judges the held closures whose robots are now placed.
  void release_held_closures(OptimizeResult* result);
  /// Every linked robot's keyframes (but `exclude`'s) at T_frame_global * global pose.
  PlacedScans linked_scans(const SE2& T_frame_global, RobotId exclude) const;
  /// One robot's keyframes at T_frame_local * local pose.
  PlacedScans robot_scans(RobotId robot, const SE2& T_frame_local) const;

  MapperOptions options_;
  std::map<RobotId, SE2> starts_;  ///< linked robots: initial T_global_local
  std::map<RobotId, SE2> hints_;   ///< set_robot_start: pinned by a prior
  std::optional<RobotId> anchor_;
  bool anchor_committed_ = false;
  LoopCloser loop_closer_;
  std::vector<KeyframeId> detect_queue_;
  std::vector<LoopClosure> loops_;
  std::vector<bool> loop_in_graph_;
  std::map<std::pair<RobotId, RobotId>, std::vector<LoopClosure>> inter_candidates_;
  std::map<RobotId, RobotId> component_parent_;
  LinkStats link_stats_;
  /// Inter-robot closures between robots of one component not yet placed: judged once placed.
  std::vector<LoopClosure> held_closures_;
  std::map<std::pair<RobotId, RobotId>, std::string> last_verdict_;  ///< dedupes link events
  bool rebuild_graph_ = true;
  bool full_resolve_ = false;
  /// Loop closures were solved in their window only: full warm-started solves (time-capped) run
  /// on the next updates until one converges.
  bool refine_pending_ = false;
  /// Updates since the last full solve (MapperOptions::refine_every_updates).
  int updates_since_refine_ = 0;
  std::map<KeyframeId, Keyframe> keyframes_;
  std::map<ObjectId, ObjectReport> reports_;
  std::map<KeyframeId, SE2> optimized_;    ///< global poses from the last optimize()
  std::map<KeyframeId, SE2> agent_poses_;  ///< add_keyframe_poses: the agents' loop-closed local poses
  std::set<RobotId> chains_changed_;       ///< robots whose chain edges in graph_ need re-measuring
  /// Unlinked robots with intra-robot loop closures: own-frame poses and the loops they solved.
  struct OwnFrame {
    size_t loops = 0;
    std::map<KeyframeId, SE2> poses;
  };
  std::map<RobotId, OwnFrame> own_frames_;
  PoseGraph2d graph_;
  uint64_t version_ = 1;        ///< anything changed
  uint64_t poses_version_ = 1;  ///< keyframes, starts or optimised poses changed

  std::map<RobotId, LocalLandmarks> local_landmarks_;
  std::map<RobotId, int> landmark_observations_;  ///< valid observations per robot
  /// Per unlinked pair: observations of both robots when last judged (retry gate).
  std::map<std::pair<RobotId, RobotId>, int> landmark_pair_judged_at_;
  std::vector<LinkEvent> landmark_link_events_;

  std::vector<ObjectConstraint> object_constraints_;  ///< sorted by report
  std::set<ObjectId> object_edges_in_graph_;          ///< reports whose observation is in graph_

  mutable uint64_t map_version_ = 0;
  mutable GlobalMapRenderer map_;  ///< redraws only the tiles of moved keyframes
  /// Keyframes whose global pose may have changed since the last global_map(); every keyframe is
  /// re-checked when map_all_moved_ or when poses_version_ changed elsewhere (tracked_ behind).
  mutable std::vector<KeyframeId> map_moved_;
  mutable bool map_all_moved_ = true;
  mutable uint64_t tracked_poses_version_ = 0;
  /// ++poses_version_, keeping tracked_poses_version_ in step when it was (map_moved_ is updated by the caller).
  void note_poses_changed();
  mutable uint64_t objects_version_ = 0;
  mutable std::vector<GlobalObject> objects_;
};

}  // namespace cairn::base
