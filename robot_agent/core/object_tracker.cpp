#include "robot_agent/core/object_tracker.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <tuple>

#include "robot_agent/core/cloud_filter.h"

namespace cairn::agent {
namespace {

ColoredCloud transform_cloud(const ColoredCloud& cloud, const Eigen::Isometry3d& T) {
  ColoredCloud out = cloud;
  for (ColoredPoint& p : out) {
    const Eigen::Vector3d q = T * Eigen::Vector3d(p.x, p.y, p.z);
    p.x = float(q.x());
    p.y = float(q.y());
    p.z = float(q.z());
  }
  return out;
}

}  // namespace

ObjectTracker::ObjectTracker(RobotId robot, const ObjectTrackerOptions& options)
    : robot_(robot), options_(options) {}

size_t ObjectTracker::num_confirmed() const {
  return size_t(std::count_if(tracks_.begin(), tracks_.end(), [](const Track& t) { return t.published; }));
}

// Greedy global nearest neighbour: pairs sorted by distance, each track and detection used once.
std::vector<int> ObjectTracker::associate(const std::vector<Eigen::Vector3d>& centroids,
                                          const std::vector<Detection>& detections) const {
  std::vector<std::tuple<double, size_t, size_t>> pairs;
  for (size_t d = 0; d < detections.size(); ++d) {
    for (size_t t = 0; t < tracks_.size(); ++t) {
      if (tracks_[t].class_name != detections[d].class_name) continue;
      const double dist = (tracks_[t].mean_local - centroids[d]).norm();
      if (dist <= options_.gate_m) pairs.emplace_back(dist, d, t);
    }
  }
  std::sort(pairs.begin(), pairs.end());
  std::vector<int> track_of(detections.size(), -1);
  std::vector<bool> used(tracks_.size(), false);
  for (const auto& [dist, d, t] : pairs) {
    if (track_of[d] >= 0 || used[t]) continue;
    track_of[d] = int(t);
    used[t] = true;
  }
  return track_of;
}

void ObjectTracker::observe(Track* t, StampNs stamp_ns, const Eigen::Vector3d& c, const ColoredCloud& cloud,
                            const std::vector<uint8_t>& thumbnail) {
  ++t->observations;
  const Eigen::Vector3d delta = c - t->mean_local;
  t->mean_local += delta / double(t->observations);
  t->m2 += delta * (c - t->mean_local).transpose();
  ColoredCloud merged = t->cloud_local;
  merged.insert(merged.end(), cloud.begin(), cloud.end());
  t->cloud_local = cap_points(voxel_downsample(merged, options_.voxel_m), size_t(options_.max_cloud_points));
  t->last_stamp_ns = stamp_ns;
  if (!thumbnail.empty()) t->thumbnail_jpeg = thumbnail;
}

bool ObjectTracker::due(const Track& t) const {
  if (t.observations < options_.min_observations) return false;
  if (!t.published) return true;
  if (t.observations <= t.observations_at_publish) return false;
  if (frame_ - t.last_publish_frame < options_.min_frames_between_publish) return false;
  const bool moved = (t.mean_local - t.published_mean).norm() > options_.republish_moved_m;
  const bool grew = double(t.cloud_local.size()) >
                    (1.0 + options_.republish_cloud_growth) * double(t.published_cloud_size);
  return moved || grew;
}

ObjectReport ObjectTracker::make_report(const Track& t, const Anchor& anchor) const {
  ObjectReport r;
  r.id = ObjectId{robot_, t.seq};
  r.class_name = t.class_name;
  r.confidence = float(1.0 - std::exp(-double(t.observations) / 3.0));
  r.stamp_ns = t.last_stamp_ns;
  r.anchor_seq = anchor.seq;
  r.observations = t.observations;
  // Object frame: origin at the centroid, axes of the local map frame.
  Eigen::Isometry3d T_local_object = Eigen::Isometry3d::Identity();
  T_local_object.translation() = t.mean_local;
  r.T_anchor_object = anchor.T_local_anchor.to_isometry3().inverse() * T_local_object;
  // Position covariance: spread of the centroid observations, rotated into the anchor frame.
  Eigen::Matrix3d pos_cov = t.m2 / double(std::max(1, t.observations - 1));
  const Eigen::Matrix3d R = r.T_anchor_object.linear();
  pos_cov = R * pos_cov * R.transpose() + Eigen::Matrix3d::Identity() * options_.min_position_variance_m2;
  r.covariance.setZero();
  r.covariance.topLeftCorner<3, 3>() = pos_cov;
  r.covariance.bottomRightCorner<3, 3>() = Eigen::Matrix3d::Identity() * options_.orientation_variance_rad2;
  r.cloud = transform_cloud(t.cloud_local, T_local_object.inverse());
  if (!r.cloud.empty()) {
    Eigen::Vector3f lo = Eigen::Vector3f::Constant(std::numeric_limits<float>::max()), hi = -lo;
    for (const ColoredPoint& p : r.cloud) {
      lo = lo.cwiseMin(Eigen::Vector3f(p.x, p.y, p.z));
      hi = hi.cwiseMax(Eigen::Vector3f(p.x, p.y, p.z));
    }
    r.size_m = hi - lo;
  }
  r.thumbnail_jpeg = t.thumbnail_jpeg;
  return r;
}

std::vector<ObjectReport> ObjectTracker::update(StampNs stamp_ns, const std::vector<Detection>& detections,
                                                const SE2& T_local_base, const Anchor& anchor) {
  ++frame_;
  const Eigen::Isometry3d T = T_local_base.to_isometry3();
  std::vector<Eigen::Vector3d> centroids;
  for (const Detection& d : detections) centroids.push_back(T * d.centroid_base);
  const std::vector<int> track_of = associate(centroids, detections);
  for (size_t d = 0; d < detections.size(); ++d) {
    Track* track = nullptr;
    if (track_of[d] >= 0) {
      track = &tracks_[size_t(track_of[d])];
    } else {
      tracks_.emplace_back();
      track = &tracks_.back();
      track->seq = next_seq_++;
      track->class_name = detections[d].class_name;
      track->mean_local = centroids[d];
    }
    observe(track, stamp_ns, centroids[d], transform_cloud(detections[d].cloud_base, T),
            detections[d].thumbnail_jpeg);
  }
  std::vector<ObjectReport> reports;
  if (anchor.seq < 0) return reports;
  for (Track& t : tracks_) {
    if (!due(t)) continue;
    reports.push_back(make_report(t, anchor));
    t.published = true;
    t.last_publish_frame = frame_;
    t.observations_at_publish = t.observations;
    t.published_mean = t.mean_local;
    t.published_cloud_size = t.cloud_local.size();
  }
  return reports;
}

}  // namespace cairn::agent
