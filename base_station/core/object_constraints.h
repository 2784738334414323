#pragma once
// Objects of interest as pose-graph constraints (issue #4): the same object seen by two robots, or
// twice by one robot from different keyframes, ties those keyframes together. Each report of a
// merged object (global_object.h) whose merge was verified (RGB-ICP, or coinciding fitted centres of
// views that share no surface) becomes a range-bearing
// observation of one 2D point node (PointNodeId = the cluster's ObjectId) from its anchor keyframe:
// the xy of T_anchor_object (the anchor's planar pose lifted to 3D, so xy in the anchor frame is the
// planar observation) with the report's xy covariance, floored. The graph puts a robust loss on them
// (KeyframePoseGraphOptions::object_loss) so that one wrong merge cannot bend the map.
// Pure function of the merged objects and the reports; the mapper recomputes it per optimize().
#include <map>
#include <vector>

#include "base_station/core/global_object.h"
#include "base_station/core/keyframe_pose_graph.h"
#include "common/object_report.h"

namespace cairn::base {

struct ObjectConstraintOptions {
  /// On by default: worlds/collapsed.yaml mission (cairn_mission), 6 merged objects constraining 3
  /// linked robots: trajectory RMSE 0.219 / 0.281 / 0.216 m off -> 0.136 / 0.186 / 0.141 m on, object
  /// error 0.215 -> 0.146 m mean xy; tests/worlds/two_robots_meet.yaml has no merged object: unchanged.
  bool enabled = true;
  /// A merged object constrains the graph only when its reports come from at least this many
  /// distinct anchor keyframes (fewer add a node and no information).
  int min_anchors = 2;
  /// Floor of the standard deviation of an observation in every direction. The robots' trackers
  /// report a few centimetres (their filtered centre), but a partial view's centre is biased
  /// towards the seen side by a good part of the object's size, and two views of one object from
  /// different sides disagree by that much.
  double min_sigma_m = 0.15;
  /// Closer observations are skipped (the bearing of a range-bearing residual is ill-defined).
  double min_range_m = 0.2;
};

/// One report of a merged object as a graph observation.
struct ObjectConstraint {
  ObjectId report;
  LandmarkEdge edge;  ///< from the anchor keyframe to the object node (the cluster's id)
};

/// The observations of every qualifying merged object, in report order. A cluster qualifies when it
/// has >= min_anchors distinct anchors and every report has >= merge.min_cloud_points cloud points
/// (then each of its joins was verified by RGB-ICP or coinciding centres; a report with too small a cloud is merged by
/// the centroid gate alone, unverified). Reports with a covariance that is not finite are skipped.
std::vector<ObjectConstraint> object_constraints(const std::vector<GlobalObject>& objects,
                                                 const std::map<ObjectId, ObjectReport>& reports,
                                                 const ObjectConstraintOptions& options,
                                                 const ObjectMergeOptions& merge);

/// Whether two constraint lists add the same edges (same reports, objects and values).
bool same_constraints(const std::vector<ObjectConstraint>& a, const std::vector<ObjectConstraint>& b);

}  // namespace cairn::base
