#include "base_station/core/global_object.h"

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <numeric>
#include <sstream>

#include "common/registration/rgb_icp.h"

namespace cairn::base {
namespace {

ColoredCloud placed_cloud(const PlacedObjectReport& p) {
  ColoredCloud out;
  out.reserve(p.report->cloud.size());
  for (const ColoredPoint& q : p.report->cloud) {
    const Eigen::Vector3d g = p.T_global_object * Eigen::Vector3d(q.x, q.y, q.z);
    if (g.allFinite()) out.push_back(ColoredPoint{float(g.x()), float(g.y()), float(g.z()), q.r, q.g, q.b});
  }
  return out;
}

Eigen::AlignedBox3d bounds(const ColoredCloud& c) {
  Eigen::AlignedBox3d box;
  for (const ColoredPoint& p : c) box.extend(Eigen::Vector3d(p.x, p.y, p.z));
  return box;
}

double weight(const ObjectReport& r) { return std::max(1, r.observations); }

/// RGB-ICP of `source` onto `target` (both global), seeded with `prior` (default: the placements).
registration::RgbIcpResult align(const ColoredCloud& source, const ColoredCloud& target, const ObjectMergeOptions& o,
                                 const Eigen::Isometry3d& prior = Eigen::Isometry3d::Identity()) {
  registration::RgbIcpOptions icp;
  icp.use_features = false;
  icp.voxel_m = o.icp_voxel_m;
  icp.max_correspondence_m = o.icp_max_correspondence_m;
  icp.max_iterations = o.icp_max_iterations;
  icp.delta_translation_m = 1e-4;
  icp.delta_rotation_rad = 1e-4;
  icp.min_points = o.min_cloud_points;
  icp.min_eigen_ratio = o.icp_min_eigen_ratio;
  return registration::rgb_icp(source, target, prior, icp);
}

int find_root(std::vector<int>& parent, int i) {
  while (parent[size_t(i)] != i) i = parent[size_t(i)] = parent[size_t(parent[size_t(i)])];
  return i;
}

GlobalObject fuse(const std::vector<PlacedObjectReport>& placed, const std::vector<int>& members,
                  const std::string& reason, const ObjectMergeOptions& o);

}  // namespace

MergeCheck check_same_object(const PlacedObjectReport& a, const PlacedObjectReport& b, const ObjectMergeOptions& o) {
  MergeCheck c;
  if (a.report->class_name != b.report->class_name) return c.reason = "different class", c;
  const ColoredCloud ca = placed_cloud(a), cb = placed_cloud(b);
  const bool clouds = int(ca.size()) >= o.min_cloud_points && int(cb.size()) >= o.min_cloud_points;
  // A report without a cloud was seen beyond the depth camera's range and placed by the ground
  // homography alone (robot_agent ObjectDetector): its height is the floor's, not the object's
  // (an exit's centre is 1 m up), so only the distance across the floor can be compared.
  const Eigen::Vector3d between = a.T_global_object.translation() - b.T_global_object.translation();
  const bool floor_height = a.report->cloud.empty() || b.report->cloud.empty();
  const double d = floor_height ? between.head<2>().norm() : between.norm();
  const double extent = std::max(a.report->size_m.maxCoeff(), b.report->size_m.maxCoeff());
  const bool cross_robot = a.report->id.robot != b.report->id.robot;
  // Two robots' placements may disagree by a few decimetres: their gate is the widest one.
  const double gate =
      cross_robot ? o.max_gate_m : std::min(o.max_gate_m, std::max(o.min_gate_m, o.size_factor * extent));
  const Eigen::AlignedBox3d ba = bounds(ca), bb = bounds(cb);
  const bool boxes = clouds && ba.exteriorDistance(bb) <= o.bbox_margin_m;
  // Touching boxes: a partial view of one end of a long object (a lying victim is 1.6 m) has its
  // centroid up to half the object's length from the whole object's centre. Such a part must then
  // lie on the whole's surface (min_part_fitness), not merely touch it.
  const bool part = boxes && d > o.max_gate_m && d <= o.max_gate_m + 0.5 * extent;
  c.candidate = d <= gate || (boxes && d <= o.max_gate_m) || part;
  const double min_fitness = part ? o.min_part_fitness : o.min_fitness;
  if (!c.candidate) return c.reason = "no overlap: centroids " + std::to_string(d) + " m apart", c;
  if (!clouds) {
    c.accepted = true;
    return c.reason = "accepted by centroid gate: a cloud has too few points to verify", c;
  }
  const bool a_smaller = ca.size() < cb.size();  // register the smaller cloud onto the larger
  const ColoredCloud& source = a_smaller ? ca : cb;
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero();  // of the registered (source) cloud
  for (const ColoredPoint& p : source) centroid += Eigen::Vector3d(p.x, p.y, p.z);
  centroid /= double(source.size());
  // First from the placements; for two robots' reports then from the reported centres made to
  // coincide (their relative placement error is larger than ICP's capture range).
  std::vector<Eigen::Isometry3d> priors{Eigen::Isometry3d::Identity()};
  if (cross_robot) {
    Eigen::Isometry3d centres = Eigen::Isometry3d::Identity();
    const Eigen::Vector3d s = (a_smaller ? a : b).T_global_object.translation();
    const Eigen::Vector3d t = (a_smaller ? b : a).T_global_object.translation();
    centres.translation() = t - s;
    priors.push_back(centres);
  }
  std::string why;
  for (size_t k = 0; k < priors.size(); ++k) {
    const registration::RgbIcpResult r = a_smaller ? align(ca, cb, o, priors[k]) : align(cb, ca, o, priors[k]);
    c.fitness = r.score;
    c.rmse_m = r.rmse_m;
    c.T_a_b = a_smaller ? r.T_target_source.inverse() : r.T_target_source;
    const double dt = (r.T_target_source * centroid - centroid).norm();  // how far the object moves
    const double dr = Eigen::AngleAxisd(r.T_target_source.linear()).angle();
    const double max_dt = cross_robot ? o.max_cross_robot_correction_m : o.max_correction_m;
    const std::string attempt = k == 0 ? "from the placements: " : "; from the centres: ";
    if (r.score < min_fitness) {
      why += attempt + "ICP fitness " + std::to_string(r.score) + " too low (" + r.reason + ")";
    } else if (r.rmse_m > o.max_rmse_m) {
      why += attempt + "ICP RMSE " + std::to_string(r.rmse_m) + " m too high";
    } else if (dt > max_dt || dr > o.max_correction_rad) {
      why += attempt + "ICP correction too large (" + std::to_string(dt) + " m, " + std::to_string(dr) + " rad)";
    } else {
      c.accepted = true;
      c.reason = "ICP " + std::string(k == 0 ? "from the placements" : "from the centres") + ": fitness " +
                 std::to_string(r.score) + ", RMSE " + std::to_string(r.rmse_m) + " m, correction " +
                 std::to_string(dt) + " m" +
                 (r.degenerate ? " (weakly constrained directions held at the placement)" : "");
      return c;
    }
  }
  // Views from opposite sides share no surface, so ICP cannot verify them. The reported centres are
  // primitive fits (robot_agent shape_fit.h), not visible-surface centroids, so one object seen from
  // two sides keeps one centre: reports whose centres coincide, whose clouds did not overlap at all
  // and whose union is no larger than one object are one object (two solid objects cannot share a
  // centre). Anything that overlapped but failed RMSE or correction stays two.
  const bool no_overlap = c.fitness < o.min_fitness;
  if (no_overlap && d <= o.max_coincident_centre_m) {
    Eigen::AlignedBox3d both = ba;
    both.extend(bb);
    const double union_xy_m = both.sizes().head<2>().maxCoeff();
    if (union_xy_m <= o.max_union_extent_factor * extent + o.bbox_margin_m) {
      c.accepted = true;
      c.fitness = 0.0;  // no ICP alignment to apply
      c.T_a_b = Eigen::Isometry3d::Identity();
      return c.reason = "centres coincide (" + std::to_string(d) + " m) and the clouds, seen from different sides, " +
                        "do not overlap; together " + std::to_string(union_xy_m) + " m across: one object",
             c;
    }
    why += "; centres coincide but the clouds together are " + std::to_string(union_xy_m) + " m across";
  }
  return c.reason = why, c;
}

std::vector<GlobalObject> merge_object_reports(const std::vector<PlacedObjectReport>& placed,
                                               const ObjectMergeOptions& options) {
  std::vector<int> parent(placed.size());
  std::iota(parent.begin(), parent.end(), 0);
  std::vector<std::string> reasons(placed.size());
  for (size_t i = 0; i < placed.size(); ++i) {
    for (size_t j = i + 1; j < placed.size(); ++j) {
      if (placed[i].report->class_name != placed[j].report->class_name) continue;
      const int a = find_root(parent, int(i)), b = find_root(parent, int(j));
      if (a == b) continue;
      const MergeCheck c = check_same_object(placed[i], placed[j], options);
      if (!c.accepted) continue;
      parent[size_t(std::max(a, b))] = std::min(a, b);  // smallest index (= smallest ObjectId) is the root
      reasons[size_t(std::min(a, b))] += (reasons[size_t(std::min(a, b))].empty() ? "" : "; ") +
                                         to_string(placed[i].report->id) + "+" + to_string(placed[j].report->id) +
                                         ": " + c.reason;
    }
  }
  std::vector<std::vector<int>> groups(placed.size());
  for (size_t i = 0; i < placed.size(); ++i) groups[size_t(find_root(parent, int(i)))].push_back(int(i));
  std::vector<GlobalObject> out;
  for (size_t g = 0; g < groups.size(); ++g)
    if (!groups[g].empty()) out.push_back(fuse(placed, groups[g], reasons[g], options));
  std::sort(out.begin(), out.end(), [](const GlobalObject& a, const GlobalObject& b) { return a.id < b.id; });
  return out;
}

namespace {

/// Union of the members' clouds, each aligned onto the most observed member's cloud by RGB-ICP
/// (kept unaligned when the check fails), then shifted so that the reference's placement error is
/// averaged like the positions: the cloud sits at the observation-weighted mean.
ColoredCloud fused_cloud(const std::vector<PlacedObjectReport>& placed, const std::vector<int>& members, int ref,
                         const Eigen::Vector3d& mean_m, const ObjectMergeOptions& o) {
  const ColoredCloud ref_cloud = placed_cloud(placed[size_t(ref)]);
  ColoredCloud all = ref_cloud;
  Eigen::Vector3d mean_in_ref = Eigen::Vector3d::Zero();
  double wsum = 0.0;
  for (int i : members) {
    const double w = weight(*placed[size_t(i)].report);
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    if (i != ref) {
      const MergeCheck c = check_same_object(placed[size_t(ref)], placed[size_t(i)], o);
      if (c.accepted && c.fitness > 0.0) T = c.T_a_b;
      for (const ColoredPoint& p : placed_cloud(placed[size_t(i)])) {
        const Eigen::Vector3d q = T * Eigen::Vector3d(p.x, p.y, p.z);
        all.push_back(ColoredPoint{float(q.x()), float(q.y()), float(q.z()), p.r, p.g, p.b});
      }
    }
    mean_in_ref += w * (T * placed[size_t(i)].T_global_object.translation());
    wsum += w;
  }
  const Eigen::Vector3d shift = mean_m - mean_in_ref / wsum;
  for (ColoredPoint& p : all) p.x += float(shift.x()), p.y += float(shift.y()), p.z += float(shift.z());
  return voxel_downsample(all, o.object_voxel_m);
}

GlobalObject fuse(const std::vector<PlacedObjectReport>& placed, const std::vector<int>& members,
                  const std::string& reason, const ObjectMergeOptions& o) {
  GlobalObject g;
  const ObjectReport& first = *placed[size_t(members.front())].report;
  g.id = first.id;
  g.class_name = first.class_name;
  g.merge_reason = reason;
  double weight_sum = 0.0;
  const ObjectReport* best = &first;
  int ref = members.front();
  for (int i : members) {
    const ObjectReport& r = *placed[size_t(i)].report;
    g.position_m += weight(r) * placed[size_t(i)].T_global_object.translation();
    weight_sum += weight(r);
    g.confidence = std::max(g.confidence, r.confidence);
    g.size_m = g.size_m.cwiseMax(r.size_m);
    g.observations += r.observations;
    g.last_stamp_ns = std::max(g.last_stamp_ns, r.stamp_ns);
    g.reports.push_back(r.id);
    g.robots.push_back(r.id.robot);
    if (r.confidence > best->confidence || (r.confidence == best->confidence && r.stamp_ns > best->stamp_ns)) best = &r;
    if (weight(r) > weight(*placed[size_t(ref)].report)) ref = i;
  }
  g.position_m /= weight_sum;
  // Covariance of the weighted mean (reports' position covariances rotated to the global frame)
  // plus the weighted scatter of the reports around it.
  Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();
  for (int i : members) {
    const ObjectReport& r = *placed[size_t(i)].report;
    const Eigen::Matrix3d R = placed[size_t(i)].T_global_object.linear();
    const double w = weight(r) / weight_sum;
    const Eigen::Vector3d d = placed[size_t(i)].T_global_object.translation() - g.position_m;
    cov += w * w * (R * r.covariance.topLeftCorner<3, 3>() * R.transpose()) + w * d * d.transpose();
  }
  g.covariance = cov;
  std::sort(g.reports.begin(), g.reports.end());
  std::sort(g.robots.begin(), g.robots.end());
  g.robots.erase(std::unique(g.robots.begin(), g.robots.end()), g.robots.end());
  g.thumbnail_jpeg = best->thumbnail_jpeg;
  g.cloud_global = fused_cloud(placed, members, ref, g.position_m, o);
  return g;
}

}  // namespace

std::string robot_frame_objects_csv(const std::map<KeyframeId, Keyframe>& keyframes,
                                    const std::map<ObjectId, ObjectReport>& reports) {
  std::ostringstream s;
  s << std::setprecision(9)
    << "id,class,robot,anchor_seq,anchor_stamp_ns,anchor_x_m,anchor_y_m,anchor_yaw_rad,x_m,y_m,"
       "z_m,observations\n";
  for (const auto& [id, r] : reports) {
    const auto kf = keyframes.find(KeyframeId{id.robot, r.anchor_seq});
    if (kf == keyframes.end()) continue;
    const Eigen::Vector3d p = (kf->second.T_local_base.to_isometry3() * r.T_anchor_object).translation();
    const SE2& A = kf->second.T_local_base;
    s << object_key(id) << ',' << r.class_name << ',' << id.robot.value << ',' << r.anchor_seq << ','
      << kf->second.stamp_ns << ',' << A.x() << ',' << A.y() << ',' << A.yaw() << ',' << p.x() << ',' << p.y() << ','
      << p.z() << ',' << r.observations << '\n';
  }
  return s.str();
}

std::string object_key(ObjectId id) { return std::to_string(id.robot.value) + "-" + std::to_string(id.seq); }

ColoredCloud voxel_downsample(const ColoredCloud& cloud, double voxel_m) {
  if (voxel_m <= 0.0) return cloud;
  return registration::voxel_grid(cloud, voxel_m);
}

}  // namespace cairn::base
