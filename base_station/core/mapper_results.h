#pragma once
// What MultiRobotMapper's calls return: the verdict on a stored sample, the outcome of an
// optimize(), and the per-robot summary.
#include <cstdint>
#include <string>
#include <vector>

#include "base_station/core/keyframe_pose_graph.h"
#include "base_station/core/robot_linker.h"
#include "common/ids.h"
#include "common/se2.h"
#include "common/time.h"

namespace cairn::base {

enum class AddStatus {
  kAccepted,   ///< stored and usable
  kPending,    ///< stored, waits for something else (e.g. an object's anchor keyframe)
  kDuplicate,  ///< already stored (or an older version of it): nothing changed
  kRejected,   ///< invalid input: nothing changed
  kConflict,   ///< would overwrite a stored record with different content (a restarted or spoofed
               ///< robot reusing its ids): refused, nothing changed
};
const char* to_string(AddStatus status);

struct AddResult {
  AddStatus status = AddStatus::kRejected;
  std::string reason;  ///< why it was rejected / pending, or notes (e.g. dropped NaN points)
  bool stored() const { return status == AddStatus::kAccepted || status == AddStatus::kPending; }
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
  std::vector<RobotId> newly_linked;  ///< robots linked by scan closures in this call
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
  int objects = 0;             ///< reports from this robot (placed or pending)
  StampNs first_stamp_ns = 0;  ///< its first keyframe's (0: none yet)
  StampNs last_stamp_ns = 0;
  /// Mission seconds from its first keyframe to its link (0 for the anchor and hinted robots); -1 while
  /// not linked.
  double time_to_link_s = -1.0;
  int32_t last_seq = -1;
  int missing_keyframes = 0;  ///< gaps in seq 0..last_seq
  /// Correction global <- robot local frame (identity when not linked); the "correction" topic.
  SE2 T_global_local;
  bool anchor = false;           ///< this robot's frame is the global frame's reference
  int inter_robot_closures = 0;  ///< accepted closures touching this robot and another
};

}  // namespace cairn::base
