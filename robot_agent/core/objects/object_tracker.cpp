#include "robot_agent/core/objects/object_tracker.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <limits>

#include "common/registration/rgb_icp.h"
#include "robot_agent/core/objects/cloud_filter.h"

namespace cairn::agent {
namespace {

// Detection noise: sigma grows with range; along the viewing ray larger than across it.
Eigen::Matrix3d detection_covariance(const Detection& d, const ObjectTrackerOptions& o) {
  if (!d.has_depth) {
    const double range = (d.centroid_base - d.camera_base).head<2>().norm();
    const double s = o.no_depth_sigma_m + o.no_depth_sigma_per_m2 * range * range;
    return Eigen::Matrix3d::Identity() * s * s;
  }
  Eigen::Vector3d ray = d.centroid_base - d.camera_base;
  const double range = ray.norm();
  ray.z() = 0.0;
  ray = ray.norm() > 1e-9 ? ray.normalized() : Eigen::Vector3d::UnitX();
  const Eigen::Vector3d side = Eigen::Vector3d::UnitZ().cross(ray);
  Eigen::Matrix3d U;
  U << ray, side, Eigen::Vector3d::UnitZ();
  const double sr = o.range_sigma_m + o.range_sigma_per_m * range;
  const double sl = o.lateral_sigma_m + o.lateral_sigma_per_m * range;
  const double sh = d.truncated_side ? o.truncated_sigma_m : sl;  // a cut blob's centre slides sideways
  const double sv = d.truncated_top_bottom ? o.truncated_sigma_m : sl;
  return U *
         Eigen::Vector3d(d.truncated_side ? std::max(sr, sh) * std::max(sr, sh) : sr * sr, sh * sh, sv * sv)
             .asDiagonal() *
         U.transpose();
}

}  // namespace

ObjectTracker::ObjectTracker(RobotId robot, const ObjectTrackerOptions& options) : robot_(robot), options_(options) {}

size_t ObjectTracker::num_confirmed() const {
  return size_t(std::count_if(tracks_.begin(), tracks_.end(), [](const Track& t) { return t.published; }));
}

ObjectTracker::Track* ObjectTracker::track_of(const std::string& cls, int target_id) {
  for (Track& t : tracks_)
    if (t.class_name == cls && t.target_id == target_id) return &t;
  return nullptr;
}

Eigen::Vector3d ObjectTracker::mean_of(const Track& t) const {
  const JpdaTracker& f = jpda_.at(t.class_name);
  const JpdaTarget* x = f.find(t.target_id);
  return x ? Eigen::Vector3d(f.position(*x)) : Eigen::Vector3d::Zero();
}

Eigen::Matrix3d ObjectTracker::covariance_of(const Track& t) const {
  const JpdaTracker& f = jpda_.at(t.class_name);
  const JpdaTarget* x = f.find(t.target_id);
  return x ? Eigen::Matrix3d(f.position_covariance(*x)) : Eigen::Matrix3d::Identity();
}

ObjectTracker::Footprint ObjectTracker::footprint_of(const Detection& d, const SE2& T_local_base) {
  Footprint f;
  if (!d.has_depth || d.truncated_side || !d.shape.converged) return f;
  f.kind = d.shape.kind;
  f.half_m = 0.5 * d.shape.size_m.head<2>();
  f.yaw_rad = d.shape.yaw_rad + T_local_base.yaw();
  f.range_m = (d.centroid_base - d.camera_base).head<2>().norm();
  return f;
}

namespace {

bool inside(const Eigen::Vector2d& centre, double half_x, double half_y, double yaw, bool box, const Eigen::Vector2d& p,
            double margin) {
  const Eigen::Vector2d q = Eigen::Rotation2Dd(-yaw) * (p - centre);
  if (!box) return q.norm() <= half_x + margin;
  return std::abs(q.x()) <= half_x + margin && std::abs(q.y()) <= half_y + margin;
}

}  // namespace

bool ObjectTracker::separate(const Footprint& a, const Eigen::Vector3d& ca, const Footprint& b,
                             const Eigen::Vector3d& cb) const {
  if (a.kind == ShapeKind::kUnknown || b.kind == ShapeKind::kUnknown) return false;  // no extent: the gate decides
  const double margin =
      options_.separation_margin_m + options_.separation_margin_per_m * std::max(a.range_m, b.range_m);
  const bool b_in_a =
      inside(ca.head<2>(), a.half_m.x(), a.half_m.y(), a.yaw_rad, a.kind == ShapeKind::kBox, cb.head<2>(), margin);
  const bool a_in_b =
      inside(cb.head<2>(), b.half_m.x(), b.half_m.y(), b.yaw_rad, b.kind == ShapeKind::kBox, ca.head<2>(), margin);
  return !b_in_a && !a_in_b;
}

void ObjectTracker::observe(Track* t, StampNs stamp_ns, const Detection& d, const Eigen::Isometry3d& T) {
  ++t->observations;
  t->last_stamp_ns = stamp_ns;
  t->saliency_sum += d.saliency;
  if (!d.thumbnail_jpeg.empty()) t->thumbnail_jpeg = d.thumbnail_jpeg;
  if (d.cloud_base.empty()) return;
  ColoredCloud view = transform_cloud(d.cloud_base, T);
  if (options_.icp_fuse_views && t->observations % std::max(1, options_.icp_every_n_observations) == 0 &&
      t->cloud_local.size() >= 30 && view.size() >= 30) {
    registration::RgbIcpOptions icp;
    icp.use_features = false;  // the odometry prior is good; features on symmetric objects are not
    icp.voxel_m = options_.icp_voxel_m;
    icp.max_correspondence_m = 0.08;
    icp.max_iterations = 15;
    icp.delta_translation_m = 1e-3;
    icp.delta_rotation_rad = 1e-3;
    const registration::RgbIcpResult r =
        registration::rgb_icp(view, t->cloud_local, Eigen::Isometry3d::Identity(), icp);
    if (r.converged && r.score > 0.5 && r.T_target_source.translation().norm() < options_.icp_max_correction_m) {
      view = transform_cloud(view, r.T_target_source);
      ++icp_fusions_;
    }
  }
  ColoredCloud merged = t->cloud_local;
  merged.insert(merged.end(), view.begin(), view.end());
  t->cloud_local = cap_points(voxel_downsample(merged, options_.voxel_m), size_t(options_.max_cloud_points));
}

void ObjectTracker::update_class(const std::string& cls, StampNs stamp_ns, const std::vector<const Detection*>& dets,
                                 const SE2& T_local_base) {
  JpdaTracker& filter = jpda_.try_emplace(cls, options_.jpda).first->second;
  const Eigen::Isometry3d T = T_local_base.to_isometry3();
  std::vector<Eigen::VectorXd> z;
  std::vector<Eigen::MatrixXd> R;
  for (const Detection* d : dets) {
    z.push_back(T * d->centroid_base);
    R.push_back(T.linear() * detection_covariance(*d, options_) * T.linear().transpose());
  }
  const std::vector<JpdaTarget> before = filter.targets();  // beta rows follow this order
  // 3D extent: a detection outside a track's footprint (and vice versa) is another object.
  std::vector<Footprint> det_fp(dets.size());
  for (size_t j = 0; j < dets.size(); ++j) det_fp[j] = footprint_of(*dets[j], T_local_base);
  std::vector<std::vector<bool>> allowed(before.size(), std::vector<bool>(dets.size(), true));
  for (size_t t = 0; t < before.size(); ++t) {
    const Track* track = track_of(cls, before[t].id);
    if (!track) continue;
    const Eigen::Vector3d centre = filter.position(before[t]);
    for (size_t j = 0; j < dets.size(); ++j) allowed[t][j] = !separate(track->footprint, centre, det_fp[j], z[j]);
  }
  const JpdaUpdate upd = filter.update(z, R, &allowed);
  for (size_t j = 0; j < dets.size(); ++j) {
    int best = -1;
    double best_beta = 0.0;
    for (size_t t = 0; t < before.size(); ++t)
      if (upd.beta[t][j] > best_beta) best_beta = upd.beta[t][j], best = int(t);
    Track* track = nullptr;
    if (best >= 0 && best_beta >= options_.min_assignment_probability) {
      track = track_of(cls, before[size_t(best)].id);
    } else if (!upd.gated[j]) {
      Track fresh;
      fresh.seq = next_seq_++;
      fresh.class_name = cls;
      fresh.target_id = filter.add(z[j], R[j]);
      tracks_.push_back(fresh);
      track = &tracks_.back();
    }
    if (!track) continue;
    if (det_fp[j].kind != ShapeKind::kUnknown) track->footprint = det_fp[j];
    observe(track, stamp_ns, *dets[j], T);
  }
}

void ObjectTracker::merge_close_tracks(const std::string& cls) {
  JpdaTracker& filter = jpda_.at(cls);
  for (size_t a = 0; a < tracks_.size(); ++a) {
    for (size_t b = a + 1; b < tracks_.size(); ++b) {
      Track &ta = tracks_[a], &tb = tracks_[b];
      if (ta.class_name != cls || tb.class_name != cls) continue;
      // Same object when closer than the merge distance in xy (homography-only views have no
      // height). Not by cloud footprint: a partial view's track would drag a good estimate away.
      if ((mean_of(ta) - mean_of(tb)).head<2>().norm() > options_.merge_distance_m) continue;
      if (separate(ta.footprint, mean_of(ta), tb.footprint, mean_of(tb))) continue;  // two objects side by side
      // Keep the published (else older) track; fold the other one in.
      const bool keep_a = ta.published || !tb.published;
      Track& keep = keep_a ? ta : tb;
      Track& gone = keep_a ? tb : ta;
      filter.merge(keep.target_id, gone.target_id);
      keep.observations += gone.observations;
      keep.saliency_sum += gone.saliency_sum;
      keep.last_stamp_ns = std::max(keep.last_stamp_ns, gone.last_stamp_ns);
      ColoredCloud merged = keep.cloud_local;
      merged.insert(merged.end(), gone.cloud_local.begin(), gone.cloud_local.end());
      keep.cloud_local = cap_points(voxel_downsample(merged, options_.voxel_m), size_t(options_.max_cloud_points));
      if (keep.thumbnail_jpeg.empty()) keep.thumbnail_jpeg = gone.thumbnail_jpeg;
      tracks_.erase(tracks_.begin() + long(keep_a ? b : a));
      return merge_close_tracks(cls);  // indices changed; few tracks, so restart
    }
  }
}

void ObjectTracker::drop_stale(StampNs stamp_ns) {
  const StampNs timeout_ns = StampNs(options_.tentative_timeout_s * 1e9);
  for (size_t i = tracks_.size(); i-- > 0;) {
    const Track& t = tracks_[i];
    if (t.published || t.observations >= options_.min_observations || stamp_ns - t.last_stamp_ns < timeout_ns) continue;
    jpda_.at(t.class_name).remove(t.target_id);
    tracks_.erase(tracks_.begin() + long(i));
  }
}

bool ObjectTracker::due(const Track& t) const {
  if (t.observations < options_.min_observations) return false;
  if (!t.published) return true;
  if (t.observations <= t.observations_at_publish) return false;
  if (frame_ - t.last_publish_frame < options_.min_frames_between_publish) return false;
  const bool moved = (mean_of(t) - t.published_mean).norm() > options_.republish_moved_m;
  const bool grew =
      double(t.cloud_local.size()) > (1.0 + options_.republish_cloud_growth) * double(t.published_cloud_size);
  const bool sharper = covariance_of(t).trace() < options_.republish_variance_ratio * t.published_variance;
  return moved || grew || sharper;
}

ObjectReport ObjectTracker::make_report(const Track& t, const Anchor& anchor) const {
  ObjectReport r;
  r.id = ObjectId{robot_, t.seq};
  r.class_name = t.class_name;
  const double mean_saliency = t.saliency_sum / std::max(1, t.observations);
  r.confidence =
      float((1.0 - std::exp(-double(t.observations) / 3.0)) * (0.8 + 0.2 * std::min(1.0, 2.0 * mean_saliency)));
  r.stamp_ns = t.last_stamp_ns;
  r.anchor_seq = anchor.seq;
  r.observations = t.observations;
  // Object frame: origin at the filtered centre, axes of the local map frame. Eqs. 20-21: the
  // anchor's planar pose (x, y, theta) lifted to SE3 carries the object into the 2D map.
  Eigen::Isometry3d T_local_object = Eigen::Isometry3d::Identity();
  T_local_object.translation() = mean_of(t);
  r.T_anchor_object = anchor.T_local_anchor.to_isometry3().inverse() * T_local_object;
  const Eigen::Matrix3d R = r.T_anchor_object.linear();
  const Eigen::Matrix3d pos_cov =
      R * covariance_of(t) * R.transpose() + Eigen::Matrix3d::Identity() * options_.min_position_variance_m2;
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
  const double dt_s = last_stamp_ns_ > 0 && stamp_ns > last_stamp_ns_ ? double(stamp_ns - last_stamp_ns_) * 1e-9 : 0.0;
  last_stamp_ns_ = std::max(last_stamp_ns_, stamp_ns);
  for (auto& [cls, filter] : jpda_) filter.predict(dt_s);
  // Classes in order of first appearance, so track numbering follows the detection order.
  std::vector<std::pair<std::string, std::vector<const Detection*>>> by_class;
  for (const Detection& d : detections) {
    if (!d.centroid_base.allFinite()) continue;
    auto it = std::find_if(by_class.begin(), by_class.end(), [&](const auto& c) { return c.first == d.class_name; });
    if (it == by_class.end()) it = by_class.insert(by_class.end(), {d.class_name, {}});
    it->second.push_back(&d);
  }
  for (const auto& [cls, dets] : by_class) {
    update_class(cls, stamp_ns, dets, T_local_base);
    merge_close_tracks(cls);
  }
  drop_stale(stamp_ns);
  std::vector<ObjectReport> reports;
  if (anchor.seq < 0) return reports;
  for (Track& t : tracks_) {
    if (!due(t)) continue;
    reports.push_back(make_report(t, anchor));
    t.published = true;
    t.last_publish_frame = frame_;
    t.observations_at_publish = t.observations;
    t.published_mean = mean_of(t);
    t.published_variance = covariance_of(t).trace();
    t.published_cloud_size = t.cloud_local.size();
  }
  return reports;
}

}  // namespace cairn::agent
