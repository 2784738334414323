#pragma once
// Tracking of detected objects in the robot's local map frame (first version of seed Sec. 3.3:
// per-class nearest-neighbour association within a gate instead of EKF + JPDA). A track
// accumulates a running-mean centroid, its spread and a voxel-filtered coloured cloud; it is
// published once seen in enough frames and re-published when it changed noticeably.
#include <Eigen/Core>
#include <string>
#include <vector>

#include "common/ids.h"
#include "common/object_report.h"
#include "common/se2.h"
#include "common/time.h"
#include "robot_agent/core/object_detector.h"

namespace cairn::agent {

struct ObjectTrackerOptions {
  double gate_m = 0.7;                    ///< association distance between centroids
  int min_observations = 3;               ///< frames before a track is published
  double republish_moved_m = 0.05;        ///< centroid change that triggers a re-publish
  double republish_cloud_growth = 0.2;    ///< relative cloud growth that triggers a re-publish
  int min_frames_between_publish = 5;     ///< rate limit per track, in processed RGB-D frames
  int max_cloud_points = 3000;
  double voxel_m = 0.025;
  double min_position_variance_m2 = 4e-4;   ///< covariance floor (2 cm sigma)
  double orientation_variance_rad2 = 1.0;   ///< orientation is not estimated
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
  std::vector<ObjectReport> update(StampNs stamp_ns, const std::vector<Detection>& detections,
                                   const SE2& T_local_base, const Anchor& anchor);

  size_t num_tracks() const { return tracks_.size(); }
  size_t num_confirmed() const;

 private:
  struct Track {
    int32_t seq = 0;
    std::string class_name;
    Eigen::Vector3d mean_local = Eigen::Vector3d::Zero();
    Eigen::Matrix3d m2 = Eigen::Matrix3d::Zero();  ///< Welford sum of squared deviations
    ColoredCloud cloud_local;
    int observations = 0;
    StampNs last_stamp_ns = 0;
    std::vector<uint8_t> thumbnail_jpeg;
    bool published = false;
    int64_t last_publish_frame = 0;
    int observations_at_publish = 0;
    Eigen::Vector3d published_mean = Eigen::Vector3d::Zero();
    size_t published_cloud_size = 0;
  };

  std::vector<int> associate(const std::vector<Eigen::Vector3d>& centroids_local,
                             const std::vector<Detection>& detections) const;
  void observe(Track* track, StampNs stamp_ns, const Eigen::Vector3d& centroid_local,
               const ColoredCloud& cloud_local, const std::vector<uint8_t>& thumbnail);
  bool due(const Track& track) const;
  ObjectReport make_report(const Track& track, const Anchor& anchor) const;

  RobotId robot_;
  ObjectTrackerOptions options_;
  std::vector<Track> tracks_;
  int32_t next_seq_ = 0;
  int64_t frame_ = 0;
};

}  // namespace cairn::agent
