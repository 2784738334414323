#include "base_station/core/object_constraints.h"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <set>

namespace cairn::base {
namespace {

/// The report's xy position covariance (anchor frame), symmetrised, eigenvalues floored at
/// min_sigma_m^2; nullopt when not finite.
std::optional<Eigen::Matrix2d> floored_xy_covariance(const ObjectReport& r, double min_sigma_m) {
  const Eigen::Matrix2d c = r.covariance.topLeftCorner<2, 2>();
  if (!c.allFinite()) return std::nullopt;
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> eig(0.5 * (c + c.transpose()));
  if (eig.info() != Eigen::Success) return std::nullopt;
  const Eigen::Vector2d values = eig.eigenvalues().cwiseMax(min_sigma_m * min_sigma_m);
  return Eigen::Matrix2d(eig.eigenvectors() * values.asDiagonal() * eig.eigenvectors().transpose());
}

/// Whether the cluster's joins were all verified (see the header) and it spans enough anchors.
bool qualifies(const GlobalObject& o, const std::map<ObjectId, ObjectReport>& reports,
               const ObjectConstraintOptions& options, const ObjectMergeOptions& merge) {
  if (o.reports.size() < 2) return false;
  std::set<KeyframeId> anchors;
  for (ObjectId id : o.reports) {
    auto it = reports.find(id);
    if (it == reports.end() || int(it->second.cloud.size()) < merge.min_cloud_points) return false;
    anchors.insert(KeyframeId{id.robot, it->second.anchor_seq});
  }
  return int(anchors.size()) >= options.min_anchors;
}

}  // namespace

std::vector<ObjectConstraint> object_constraints(const std::vector<GlobalObject>& objects,
                                                 const std::map<ObjectId, ObjectReport>& reports,
                                                 const ObjectConstraintOptions& options,
                                                 const ObjectMergeOptions& merge) {
  std::vector<ObjectConstraint> out;
  if (!options.enabled) return out;
  for (const GlobalObject& o : objects) {
    if (!qualifies(o, reports, options, merge)) continue;
    for (ObjectId id : o.reports) {
      const ObjectReport& r = reports.at(id);
      const Eigen::Vector2d p = r.T_anchor_object.translation().head<2>();
      const double range_m = p.norm();
      const auto covariance = floored_xy_covariance(r, options.min_sigma_m);
      if (!p.allFinite() || range_m < std::max(options.min_range_m, 0.01) || !covariance) continue;
      // Polar standard deviations of the point's covariance (radial, tangential / range); the
      // correlation between them is dropped (exact for the isotropic floor).
      const Eigen::Vector2d u = p / range_m, v(-u.y(), u.x());
      LandmarkEdge e;
      e.from = KeyframeId{id.robot, r.anchor_seq};
      e.landmark = o.id;
      e.range_m = range_m;
      e.bearing_rad = std::atan2(p.y(), p.x());
      e.sigma_range_m = std::sqrt(double(u.transpose() * *covariance * u));
      e.sigma_bearing_rad = std::sqrt(double(v.transpose() * *covariance * v)) / range_m;
      out.push_back(ObjectConstraint{id, e});
    }
  }
  std::sort(out.begin(), out.end(),
            [](const ObjectConstraint& a, const ObjectConstraint& b) { return a.report < b.report; });
  return out;
}

bool same_constraints(const std::vector<ObjectConstraint>& a, const std::vector<ObjectConstraint>& b) {
  if (a.size() != b.size()) return false;
  for (size_t i = 0; i < a.size(); ++i) {
    const LandmarkEdge &x = a[i].edge, &y = b[i].edge;
    if (a[i].report != b[i].report || x.from != y.from || x.landmark != y.landmark || x.range_m != y.range_m ||
        x.bearing_rad != y.bearing_rad || x.sigma_range_m != y.sigma_range_m ||
        x.sigma_bearing_rad != y.sigma_bearing_rad) {
      return false;
    }
  }
  return true;
}

}  // namespace cairn::base
