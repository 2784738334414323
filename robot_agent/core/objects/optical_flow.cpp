#include "robot_agent/core/objects/optical_flow.h"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>
#include <opencv2/video/tracking.hpp>

namespace cairn::agent {

FoeResult estimate_foe(const std::vector<FlowVector>& flow, double min_flow_px) {
  FoeResult r;
  Eigen::Matrix2d A = Eigen::Matrix2d::Zero();
  Eigen::Vector2d b = Eigen::Vector2d::Zero();
  for (const FlowVector& f : flow) {
    const double len = f.flow_px.norm();
    if (!(len >= min_flow_px) || !f.p_px.allFinite()) continue;
    const Eigen::Vector2d n(-f.flow_px.y() / len, f.flow_px.x() / len);
    A += n * n.transpose();
    b += n * n.dot(f.p_px);
    ++r.used;
  }
  if (r.used < 2) {
    r.reason = "fewer than 2 usable flow vectors";
    return r;
  }
  const Eigen::JacobiSVD<Eigen::Matrix2d> svd(A);
  if (svd.singularValues()(1) < 1e-6 * std::max(1.0, svd.singularValues()(0))) {
    r.reason = "flow vectors are parallel: the FOE is at infinity (pure sideways motion or rotation)";
    return r;
  }
  r.foe_px = A.ldlt().solve(b);
  double sq = 0.0;
  for (const FlowVector& f : flow) {
    const double len = f.flow_px.norm();
    if (!(len >= min_flow_px)) continue;
    const Eigen::Vector2d n(-f.flow_px.y() / len, f.flow_px.x() / len);
    sq += std::pow(n.dot(r.foe_px - f.p_px), 2);
  }
  r.score = std::sqrt(sq / r.used);
  r.converged = true;
  return r;
}

double time_to_contact_s(const FlowVector& f, const Eigen::Vector2d& foe_px, double dt_s) {
  const Eigen::Vector2d d = f.p_px - foe_px;
  const double D = d.norm();
  if (D < 1e-9) return -1.0;
  const double dD_dt = d.dot(f.flow_px) / D / dt_s;  // radial expansion rate
  return dD_dt > 1e-9 ? D / dD_dt : -1.0;
}

double closest_approach_m(const Eigen::Vector3d& x, const Eigen::Vector3d& s) {
  const double ss = s.dot(s);
  if (ss <= 0.0) return x.norm();
  return std::sqrt(std::max(0.0, x.dot(x) - std::pow(s.dot(x), 2) / ss));
}

CollisionEstimate assess_collision(const std::vector<FlowVector>& flow, const CameraIntrinsics& K, double dt_s,
                                   double speed_mps, const OpticalFlowOptions& o) {
  CollisionEstimate e;
  e.tracked = int(flow.size());
  if (!(dt_s > 0.0) || K.fx <= 0.0 || K.fy <= 0.0) {
    e.reason = "invalid frame interval or intrinsics";
    return e;
  }
  if (!(speed_mps >= o.min_speed_mps)) {
    e.reason = "robot not translating: optical flow carries no depth";
    return e;
  }
  const FoeResult foe = estimate_foe(flow);
  if (!foe.converged) {
    e.reason = foe.reason;
    return e;
  }
  e.foe_px = foe.foe_px;
  // Motion direction s (Eq. 5) in the camera frame: the FOE's viewing ray.
  const Eigen::Vector3d s((foe.foe_px.x() - K.cx) / K.fx, (foe.foe_px.y() - K.cy) / K.fy, 1.0);
  const double speed_along_axis = speed_mps / s.norm();  // c_z
  std::vector<double> taus, dmins;
  for (const FlowVector& f : flow) {
    // Near the FOE the radial flow is tiny and tau is noise: skip those features.
    if ((f.p_px - foe.foe_px).norm() < o.min_foe_distance_px) continue;
    const double tau = time_to_contact_s(f, foe.foe_px, dt_s);
    if (tau <= 0.0 || tau > o.horizon_s) continue;
    const double z = tau * speed_along_axis;  // Eq. 3: z = c_z * D / (dD/dt)
    const Eigen::Vector3d x((f.p_px.x() - K.cx) / K.fx * z, (f.p_px.y() - K.cy) / K.fy * z, z);
    const double d_min = closest_approach_m(x, s);
    taus.push_back(tau);
    dmins.push_back(d_min);
    if (d_min < o.robot_radius_m) ++e.risky;
  }
  // Robust minima: a low percentile, so one bad track does not raise an alarm.
  auto low = [&](std::vector<double> v) {
    if (v.empty()) return -1.0;
    const size_t k = size_t(o.robust_percentile * double(v.size() - 1));
    std::nth_element(v.begin(), v.begin() + long(k), v.end());
    return v[k];
  };
  e.min_ttc_s = low(taus);
  e.min_d_m = low(dmins);
  e.converged = true;
  if (e.risky >= o.min_risky_features && e.min_ttc_s > 0.0) {
    e.collision_risk = float(std::clamp(1.0 - e.min_ttc_s / o.horizon_s, 0.1, 1.0));
  }
  return e;
}

struct OpticalFlowCollision::State {
  cv::Mat previous_grey;
  StampNs previous_stamp_ns = 0;
};

OpticalFlowCollision::OpticalFlowCollision(const OpticalFlowOptions& options)
    : options_(options), state_(std::make_unique<State>()) {}
OpticalFlowCollision::~OpticalFlowCollision() = default;
OpticalFlowCollision::OpticalFlowCollision(OpticalFlowCollision&&) noexcept = default;
OpticalFlowCollision& OpticalFlowCollision::operator=(OpticalFlowCollision&&) noexcept = default;

CollisionEstimate OpticalFlowCollision::update(const RgbdFrame& frame, double speed_mps, double yaw_rate_radps) {
  last_ = CollisionEstimate{};
  if (!frame.valid()) {
    last_.reason = "invalid frame";
    return last_;
  }
  const cv::Mat rgb(frame.intrinsics.height, frame.intrinsics.width, CV_8UC3, const_cast<uint8_t*>(frame.rgb.data()));
  cv::Mat grey;
  cv::cvtColor(rgb, grey, cv::COLOR_RGB2GRAY);
  State& s = *state_;
  const bool have_previous =
      !s.previous_grey.empty() && s.previous_grey.size() == grey.size() && frame.stamp_ns > s.previous_stamp_ns;
  const double dt_s = have_previous ? double(frame.stamp_ns - s.previous_stamp_ns) * 1e-9 : 0.0;
  const cv::Mat previous = s.previous_grey;
  s.previous_grey = grey;
  s.previous_stamp_ns = frame.stamp_ns;
  if (!have_previous) {
    last_.reason = "first frame";
    return last_;
  }
  if (std::abs(yaw_rate_radps) > options_.max_yaw_rate_radps) {
    last_.reason = "turning: rotational flow dominates";
    return last_;
  }
  std::vector<cv::Point2f> p0, p1;
  cv::goodFeaturesToTrack(previous, p0, options_.max_features, options_.feature_quality,
                          options_.min_feature_distance_px);
  if (p0.size() < 3) {
    last_.reason = "too little texture for optical flow";
    return last_;
  }
  std::vector<uchar> status;
  std::vector<float> err;
  cv::calcOpticalFlowPyrLK(previous, grey, p0, p1, status, err, cv::Size(options_.window_px, options_.window_px),
                           options_.pyramid_levels);
  // Remove the rotational flow of a yaw about the camera's vertical axis (small-angle model).
  const CameraIntrinsics& K = frame.intrinsics;
  const double yaw = yaw_rate_radps * dt_s;
  std::vector<FlowVector> flow;
  for (size_t i = 0; i < p0.size(); ++i) {
    if (!status[i]) continue;
    FlowVector f;
    f.p_px = Eigen::Vector2d(p1[i].x, p1[i].y);
    const double xn = (p0[i].x - K.cx) / K.fx, yn = (p0[i].y - K.cy) / K.fy;
    const Eigen::Vector2d rot(yaw * K.fx * (1.0 + xn * xn), yaw * K.fy * xn * yn);  // yaw left: image moves right
    f.flow_px = Eigen::Vector2d(p1[i].x - p0[i].x, p1[i].y - p0[i].y) - rot;
    flow.push_back(f);
  }
  last_ = assess_collision(flow, K, dt_s, speed_mps, options_);
  return last_;
}

}  // namespace cairn::agent
