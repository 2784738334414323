#pragma once
// An object of interest in the global frame, possibly merged from reports of several robots, and
// the base station's duplicate merging: candidate pairs of the same class whose clouds overlap
// (bounding boxes intersect, or centroids closer than a class-size-aware gate), verified by RGB-ICP
// (seed paper Algorithm 3, common/registration) between the two clouds in the global frame and
// accepted when fitness, RMSE and the size of the correction pass; accepted pairs are joined
// (union-find). Reports of different robots are also tried from their centres made to coincide
// (robust to the robots' relative placement error; max_cross_robot_correction_m). Views from
// opposite sides share no surface for ICP: they are one object when their fitted centres coincide
// and their clouds together are one object's size (max_coincident_centre_m). A merged object's cloud is the union of
// its reports' clouds after alignment onto the most observed report, voxel-downsampled; its position is the
// observation-weighted mean.
#include <Eigen/Geometry>
#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "common/ids.h"
#include "common/keyframe.h"
#include "common/object_report.h"
#include "common/point_cloud.h"
#include "common/time.h"

namespace cairn::base {

/// The operator's word on an object (the console): a person looked at its photo and cloud.
enum class ObjectVerdict : uint8_t { kUnreviewed = 0, kConfirmed = 1, kFalse = 2 };
inline const char* to_string(ObjectVerdict v) {
  return v == ObjectVerdict::kConfirmed ? "confirmed" : v == ObjectVerdict::kFalse ? "false" : "unreviewed";
}

struct GlobalObject {
  /// The id the team first saw it under (ObjectIdRegistry); merge_object_reports gives the smallest
  /// ObjectId among its reports.
  ObjectId id;
  /// Invalid: position_m is in the global frame. Else the robot (not linked yet) in whose own local
  /// frame position_m and cloud_global are (robot_frame_objects.h).
  RobotId frame;
  std::vector<ObjectId> aliases;  ///< other ids it was shown under before objects merged (sorted)
  std::string class_name;
  float confidence = 0.f;                                           ///< max over reports
  Eigen::Vector3d position_m = Eigen::Vector3d::Zero();             ///< global frame, observation-weighted
  Eigen::Matrix3d covariance = Eigen::Matrix3d::Identity() * 0.01;  ///< of position_m, global
  Eigen::Vector3f size_m = Eigen::Vector3f::Zero();                 ///< max extent over reports
  int observations = 0;                                             ///< sum over reports
  StampNs last_stamp_ns = 0;
  std::vector<ObjectId> reports;                       ///< sorted
  std::vector<RobotId> robots;                         ///< sorted, unique
  ColoredCloud cloud_global;                           ///< union of the reports' aligned clouds, voxel-downsampled
  std::vector<uint8_t> thumbnail_jpeg;                 ///< of the most confident report (may be empty)
  std::string merge_reason;                            ///< how the reports were joined (empty for a single report)
  ObjectVerdict verdict = ObjectVerdict::kUnreviewed;  ///< the operator's (ObjectVerdicts::apply)
  std::string verdict_note;                            ///< the operator's note, if any
};

struct ObjectMergeOptions {
  /// Candidate gate on centroid distance: max(min_gate_m, size_factor * largest extent of the two
  /// reports), never above max_gate_m (MapperOptions::merge_distance_m); for reports of two
  /// different robots max_gate_m (their relative placement error adds to the distance).
  double min_gate_m = 0.3;
  double size_factor = 2.0;
  double max_gate_m = 0.75;
  double bbox_margin_m = 0.02;  ///< bounding boxes closer than this also make a candidate
  /// RGB-ICP verification in the global frame (prior: the placements; no features, the placement is
  /// good to a few decimetres and features on symmetric objects are ambiguous).
  double icp_voxel_m = 0.03;
  double icp_max_correspondence_m = 0.06;
  int icp_max_iterations = 30;
  /// Weakly constrained directions (a partial cylinder turning about its axis) are held fixed:
  /// partial views from different sides must not slide around the object.
  double icp_min_eigen_ratio = 1e-2;
  double min_fitness = 0.3;  ///< fraction of the smaller cloud within the gate after ICP
  /// A report farther than max_gate_m whose box touches a larger report's (a part of a long object
  /// seen alone, its centroid up to half the object's length off) must lie on the other's surface.
  double min_part_fitness = 0.8;
  double max_rmse_m = 0.04;
  double max_correction_m = 0.3;  ///< larger ICP corrections mean another object (same robot)
  /// Reports of different robots: their placements come from different pose-graph links and may be
  /// off by a few decimetres relative to each other (0.22-0.28 m RMSE in the simulated missions).
  /// When ICP from the placements fails, it is retried from the two reported centres made to
  /// coincide, and the correction may then reach this much.
  double max_cross_robot_correction_m = 0.45;
  double max_correction_rad = 0.5;
  /// Reports whose clouds do not overlap (views from opposite sides: ICP fitness below min_fitness)
  /// are still one object when their centres (primitive fits, not surface centroids) are at most
  /// this far apart and the two clouds together are at most max_union_extent_factor times the larger
  /// report's extent across (+ bbox_margin_m).
  double max_coincident_centre_m = 0.10;
  double max_union_extent_factor = 1.3;
  int min_cloud_points = 10;     ///< below this a report is merged by centroid gate alone
  double object_voxel_m = 0.02;  ///< voxel of the merged clouds
};

/// A report placed in the global frame through its anchor keyframe.
struct PlacedObjectReport {
  const ObjectReport* report = nullptr;
  Eigen::Isometry3d T_global_object = Eigen::Isometry3d::Identity();
};

/// Outcome of verifying one candidate pair.
struct MergeCheck {
  bool candidate = false;  ///< same class and overlapping (box or gate)
  bool accepted = false;
  double fitness = 0.0, rmse_m = 0.0;
  Eigen::Isometry3d T_a_b = Eigen::Isometry3d::Identity();  ///< correction: b's cloud onto a's (global)
  std::string reason;
};

/// Verifies whether two placed reports are one object (see the file comment).
MergeCheck check_same_object(const PlacedObjectReport& a, const PlacedObjectReport& b, const ObjectMergeOptions& o);

/// Merges placed reports into objects, sorted by id.
std::vector<GlobalObject> merge_object_reports(const std::vector<PlacedObjectReport>& placed,
                                               const ObjectMergeOptions& options);

/// Every stored report in its own robot's local frame (T_local_anchor * T_anchor_object, the anchor
/// keyframe's pose as the robot sent it), as CSV: id,class,robot,anchor_seq,anchor_stamp_ns,
/// anchor_x_m,anchor_y_m,anchor_yaw_rad (T_local_anchor),x_m,y_m,z_m,observations. With each robot's true start this
/// scores the object pipeline without the robots' placement error at the base (tools/eval). Reports whose anchor has
/// not arrived are left out.
std::string robot_frame_objects_csv(const std::map<KeyframeId, Keyframe>& keyframes,
                                    const std::map<ObjectId, ObjectReport>& reports);

/// "<robot>-<seq>", safe in URLs and file names (e.g. "1-3").
std::string object_key(ObjectId id);

/// Averages points (position and colour) per cubic voxel; deterministic output order.
ColoredCloud voxel_downsample(const ColoredCloud& cloud, double voxel_m);

}  // namespace cairn::base
