#pragma once
// Tracking of detected objects in the robot's local map frame (seed paper Sec. 3.3: EKF with joint
// probabilistic data association). One JpdaTracker per class holds each object's 3D centre
// (constant-position model, process noise absorbing SLAM drift); a detection's camera-frame noise
// (range noise larger than lateral) is rotated into the local frame, which is the EKF's
// linearisation of the frame change. A detection updates the track that JPDA gives it with
// probability >= min_assignment_probability; detections outside every gate start tentative tracks;
// ambiguous ones only update the filters. Each track fuses its views into one coloured cloud,
// aligned by RGB-ICP (Algorithm 3) when that converges. A track is published once seen in
// min_observations frames and re-published when its estimate improved (moved, cloud grew,
// covariance shrank). Close tracks of the same class are merged, unless their fitted 3D footprints
// (box / cylinder / sphere from shape_fit) exclude each other's centres: then they are two objects
// side by side, and a detection outside a track's footprint is kept out of its JPDA gate too.
#include <Eigen/Core>
#include <map>
#include <string>
#include <vector>

#include "common/ids.h"
#include "common/object_report.h"
#include "common/se2.h"
#include "common/time.h"
#include "robot_agent/core/objects/jpda_tracker.h"
#include "robot_agent/core/objects/object_detector.h"

namespace cairn::agent {

struct ObjectTrackerOptions {
  JpdaOptions jpda{3, false, 2e-4, 16.0, 0.8, 1e-2, Association::kJpda, 200000};
  double min_assignment_probability = 0.5;
  double lateral_sigma_m = 0.03, lateral_sigma_per_m = 0.01;  ///< detection noise across the ray
  double range_sigma_m = 0.05, range_sigma_per_m = 0.02;      ///< along the ray
  double no_depth_sigma_m = 0.4;                              ///< homography-only detections, plus:
  double no_depth_sigma_per_m2 = 0.015;                       ///< the ground homography's range error grows as range^2
  double truncated_sigma_m = 0.5;                             ///< blobs cut by the image border (that axis only)
  double merge_distance_m = 0.5;                              ///< same-class tracks closer than this are one object...
  /// ...unless their 3D extents say otherwise: a detection (or track) whose centre lies outside a
  /// track's fitted footprint (box, cylinder or sphere, grown by this margin + the per-metre part
  /// times the range), and whose own footprint excludes the track's centre, is another object: it is
  /// kept out of that track's JPDA gate and may start a track even inside the gate.
  double separation_margin_m = 0.05, separation_margin_per_m = 0.02;
  int min_observations = 3;               ///< frames before a track is published
  double tentative_timeout_s = 20.0;      ///< unpublished tracks without a hit for this long are dropped
  double republish_moved_m = 0.05;        ///< centre change that triggers a re-publish
  double republish_cloud_growth = 0.2;    ///< relative cloud growth that triggers a re-publish
  double republish_variance_ratio = 0.7;  ///< position variance shrinking below this ratio, too
  int min_frames_between_publish = 5;     ///< rate limit per track, in processed RGB-D frames
  int max_cloud_points = 3000;
  double voxel_m = 0.025;
  bool icp_fuse_views = true;          ///< align each view onto the track cloud with RGB-ICP
  double icp_max_correction_m = 0.15;  ///< larger ICP corrections are not trusted
  int icp_every_n_observations = 4;    ///< ICP cost bound: other views are fused by odometry only
  double icp_voxel_m = 0.04;
  double min_position_variance_m2 = 4e-4;  ///< covariance floor (2 cm sigma)
  double orientation_variance_rad2 = 1.0;  ///< orientation is not estimated
};

/// The keyframe an object report is expressed against.
struct Anchor {
  int32_t seq = -1;  ///< -1: no keyframe yet (nothing is published)
  SE2 T_local_anchor;
};

class ObjectTracker {
 public:
  ObjectTracker(RobotId robot, const ObjectTrackerOptions& options = {});

  /// Associates one frame's detections (base frame) given the robot pose at the frame's stamp;
  /// returns the reports due (new confirmations and re-publications).
  std::vector<ObjectReport> update(StampNs stamp_ns, const std::vector<Detection>& detections, const SE2& T_local_base,
                                   const Anchor& anchor);

  size_t num_tracks() const { return tracks_.size(); }
  size_t num_confirmed() const;
  int icp_fusions() const { return icp_fusions_; }

 private:
  /// Fitted footprint in the local frame (kind kUnknown: none).
  struct Footprint {
    ShapeKind kind = ShapeKind::kUnknown;
    Eigen::Vector2d half_m = Eigen::Vector2d::Zero();  ///< box half sides; radius in x otherwise
    double yaw_rad = 0.0;
    double range_m = 0.0;  ///< of the view it came from
  };
  struct Track {
    int32_t seq = 0;
    Footprint footprint;
    std::string class_name;
    int target_id = 0;  ///< in jpda_[class_name]
    ColoredCloud cloud_local;
    int observations = 0;
    StampNs last_stamp_ns = 0;
    double saliency_sum = 0.0;
    std::vector<uint8_t> thumbnail_jpeg;
    bool published = false;
    int64_t last_publish_frame = 0;
    int observations_at_publish = 0;
    Eigen::Vector3d published_mean = Eigen::Vector3d::Zero();
    double published_variance = 0.0;
    size_t published_cloud_size = 0;
  };

  void update_class(const std::string& cls, StampNs stamp_ns, const std::vector<const Detection*>& dets,
                    const SE2& T_local_base);
  void observe(Track* track, StampNs stamp_ns, const Detection& d, const Eigen::Isometry3d& T_local_base);
  void merge_close_tracks(const std::string& cls);
  static Footprint footprint_of(const Detection& d, const SE2& T_local_base);
  bool separate(const Footprint& a, const Eigen::Vector3d& centre_a, const Footprint& b,
                const Eigen::Vector3d& centre_b) const;
  void drop_stale(StampNs stamp_ns);
  Track* track_of(const std::string& cls, int target_id);
  Eigen::Vector3d mean_of(const Track& t) const;
  Eigen::Matrix3d covariance_of(const Track& t) const;
  bool due(const Track& track) const;
  ObjectReport make_report(const Track& track, const Anchor& anchor) const;

  RobotId robot_;
  ObjectTrackerOptions options_;
  std::map<std::string, JpdaTracker> jpda_;
  std::vector<Track> tracks_;
  int32_t next_seq_ = 0;
  int64_t frame_ = 0;
  StampNs last_stamp_ns_ = 0;
  int icp_fusions_ = 0;
};

}  // namespace cairn::agent
