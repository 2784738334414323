#pragma once
// MultiRobotMapper: the base station's merger (DESIGN.md "Base station" 1, 4, 5). It stores every
// robot's keyframes (odometry chains in each robot's local frame) and object reports, lets the
// RobotLinker decide which robots are placed where, keeps a Ceres SE2 pose graph of the linked
// robots, and derives the global occupancy grid and the merged objects in global coordinates.
// Three parts, as Cartographer splits its pose graph: the data (MapperData), the link decisions
// (RobotLinker) and the graph with its update (here). add_* only store; optimize() decides and
// solves, step by step. On a new link the graph is re-solved from a LAGO initialisation; other
// updates are incremental and warm-started. Unlinked robots' data is kept but not placed.
// Single-threaded and deterministic; queries rebuild cached results lazily, so even const methods
// must not be called concurrently (the console works on snapshots, see console/snapshot.h).
#include <map>
#include <optional>
#include <set>
#include <vector>

#include "base_station/core/global_map_cache.h"
#include "base_station/core/global_object.h"
#include "base_station/core/keyframe_pose_graph.h"
#include "base_station/core/mapper_data.h"
#include "base_station/core/mapper_options.h"
#include "base_station/core/mapper_results.h"
#include "base_station/core/merged_map.h"
#include "base_station/core/object_constraints.h"
#include "base_station/core/object_id_registry.h"
#include "base_station/core/robot_frame_objects.h"
#include "base_station/core/robot_linker.h"

namespace cairn::base {

class MultiRobotMapper {
 public:
  explicit MultiRobotMapper(const MapperOptions& options = {});

  // Ingest: each call only stores (decisions happen in optimize()).
  /// A hint that places a robot directly: its local frame sits at T_global_local (pinned by a prior).
  void set_robot_start(RobotId robot, const SE2& T_global_local);
  /// Roughly where a robot entered (EntryHint): bounds its link search and, when its closures agree,
  /// lets it link sooner; never places it by itself. False (nothing stored) when not finite or a
  /// sigma is not positive.
  bool set_entry_hint(RobotId robot, const EntryHint& hint);
  /// The operator placed an unlinked robot's map at T_global_local (the console): verified at the
  /// next optimize() (RobotLinker, robot_linker_operator.cpp), never a link by itself. False
  /// (nothing stored) when the robot id is invalid or the pose not finite.
  bool request_alignment(RobotId robot, const SE2& T_global_local);
  const std::map<RobotId, AlignmentVerdict>& alignments() const { return linker_.alignments(); }
  AddResult add_keyframe(const Keyframe& keyframe);
  /// The agent's loop-closed estimate of its keyframes (common/keyframe.h): from the next
  /// optimize() the chain between consecutive keyframes follows it instead of the front end's
  /// edges (edges re-measured in place, then a full warm-started solve). It replaces the robot's
  /// previous one. Rejected whole (nothing changes) when a pose is not finite, a seq is negative
  /// or repeated.
  AddResult add_keyframe_poses(const KeyframePoses& update);
  AddResult add_object(const ObjectReport& report);

  /// Links robots (RobotLinker::update), updates the pose graph of all linked robots and solves.
  OptimizeResult optimize();
  /// True while loop closures have not been solved to convergence over the whole graph: call
  /// optimize() until false before exporting a final map.
  bool refinement_pending() const { return refine_pending_; }

  // What the outputs read.
  MergedMap merged() const;
  std::vector<RobotSummary> robots() const;
  /// Merged objects of linked robots, sorted by id (ids stable for the mission: ObjectIdRegistry).
  std::vector<GlobalObject> objects() const;
  /// Objects of robots not linked yet, each in its robot's own frame (robot_frame_objects.h).
  std::vector<GlobalObject> unplaced_objects() const;
  /// What the object-id registry learnt since the last call (whenever objects were computed), to
  /// journal.
  std::vector<ObjectIdRegistry::Entry> take_object_id_entries();
  /// An object-id fact journaled before a restart; before any object is computed (false: refused).
  bool restore_object_id(const ObjectIdRegistry::Entry& e) { return object_ids_.restore(e); }
  /// Each unlinked robot's own map (robot_frame_objects.h), redrawn incrementally.
  const std::vector<RobotFrameMap>& robot_frame_maps() const;
  /// Reports whose anchor keyframe has not arrived yet.
  std::vector<ObjectId> pending_objects() const { return data_.pending_objects(); }
  /// Occupancy grid of every linked keyframe's scan at its current global pose.
  const OccupancyGrid& global_map() const { return map_.render(data_); }
  double mapped_area_m2() const { return global_map().known_area_m2(); }
  /// Bumped whenever any global pose or object may have changed.
  uint64_t version() const { return version_; }

  // The parts, and shorthands into them.
  const MapperData& data() const { return data_; }
  const KeyframePoseGraph& graph() const { return graph_; }
  const MapperOptions& options() const { return options_; }
  bool linked(RobotId robot) const { return data_.linked(robot); }
  std::optional<SE2> global_pose(KeyframeId id) const { return data_.global_pose(id); }
  Trajectory global_trajectory(RobotId robot) const { return data_.global_trajectory(robot); }
  SE2 refined_local_pose(KeyframeId id) const { return data_.refined_local_pose(id); }
  SE2 agent_local_pose(KeyframeId id) const { return data_.agent_local_pose(id); }
  const std::map<KeyframeId, Keyframe>& keyframes() const { return data_.keyframes; }
  const std::map<ObjectId, ObjectReport>& object_reports() const { return data_.reports; }
  const std::vector<LoopClosure>& loop_closures() const { return data_.loops; }
  const std::map<RobotId, LocalLandmarks>& local_landmarks() const { return data_.local_landmarks; }
  const LinkStats& link_stats() const { return linker_.stats(); }
  const KeyframeLoopCloserStats& loop_closer_stats() const { return linker_.loop_closer_stats(); }
  const std::vector<LinkEvent>& landmark_link_events() const { return linker_.landmark_link_events(); }
  /// Optimised global positions of the landmarks seen by linked robots.
  std::map<LandmarkId, Eigen::Vector2d> landmarks() const { return graph_.landmark_estimates(); }
  /// The object observations of the last optimize() (each report of a verified merged object).
  const std::vector<ObjectConstraint>& object_observations() const { return object_constraints_; }

 private:
  // The graph and its update (multi_robot_mapper_graph.cpp).
  /// Adds each linked robot's new keyframes, the loop, landmark and object edges, and solves: the
  /// whole graph from LAGO after a link, else the new keyframes' window or a full refinement.
  void update_graph(bool full_resolve, OptimizeResult* result);
  /// Starts over from an empty graph when something already in it changed.
  void rebuild_graph_if_needed();
  /// Re-measures in place the chain edges of robots whose agents sent new loop-closed poses.
  void remeasure_changed_chains();
  /// The robot's keyframes not in the graph yet, chained to its last one in it (or pinned).
  void add_robot_chain(RobotId robot, OptimizeResult* result);
  void add_loop_edges();
  /// Range-bearing edges of the robot's keyframes in the graph that have none yet.
  void add_landmark_edges(RobotId robot);
  /// Each sighting whose two robots are placed: a point node observed from both (sightings.h).
  void add_sighting_edges();
  void solve(bool full_resolve, std::vector<KeyframeId> active, OptimizeResult* result);
  // Objects (multi_robot_mapper_objects.cpp).
  /// Recomputes the object observations from the current merge; asks for a graph rebuild when an
  /// observation already in the graph changed or went away.
  void refresh_object_constraints();
  void add_object_edges();
  std::vector<GlobalObject> compute_objects() const;
  void refresh_objects() const;
  ObjectMergeOptions merge_options() const;
  void count_graph(OptimizeResult* result) const;
  /// Records when robots got linked (MapperData::linked_at_ns), in mission time.
  void note_link_times();

  MapperOptions options_;
  MapperData data_;
  RobotLinker linker_;
  KeyframePoseGraph graph_;
  std::vector<bool> loop_in_graph_;                   ///< per data_.loops entry
  std::set<RobotId> chains_changed_;                  ///< robots whose chain edges in graph_ need re-measuring
  std::vector<ObjectConstraint> object_constraints_;  ///< sorted by report
  std::vector<bool> sighting_done_;                   ///< per data_.sightings entry: in graph_, or never usable
  std::set<ObjectId> object_edges_in_graph_;          ///< reports whose observation is in graph_
  bool rebuild_graph_ = true;
  /// Loop closures were solved in their window only: full warm-started solves (time-capped) run
  /// on the next updates until one converges.
  bool refine_pending_ = false;
  int updates_since_refine_ = 0;  ///< since the last full solve (MapperOptions::refine_every_updates)
  uint64_t version_ = 1;          ///< anything changed
  mutable GlobalMapCache map_;
  mutable uint64_t objects_version_ = 0;
  mutable std::vector<GlobalObject> objects_, unplaced_;
  mutable ObjectIdRegistry object_ids_;  ///< ids as first shown, whenever objects are first computed
  mutable uint64_t frame_maps_version_ = 0;
  mutable std::vector<RobotFrameMap> frame_maps_;
  mutable std::map<RobotId, GlobalMapRenderer> frame_renderers_;  ///< one per unlinked robot
};

}  // namespace cairn::base
