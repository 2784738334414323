#include "robot_agent/core/objects/optical_flow.h"

#include <gtest/gtest.h>

#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>
#include <random>

namespace cairn::agent {
namespace {

const CameraIntrinsics kK{320, 240, 300.0, 300.0, 160.0, 120.0, 0.001};

Eigen::Vector2d project(const Eigen::Vector3d& p) {
  return Eigen::Vector2d(kK.fx * p.x() / p.z() + kK.cx, kK.fy * p.y() / p.z() + kK.cy);
}

// Static points seen by a camera translating with velocity c (camera frame) for dt (Eq. 1).
std::vector<FlowVector> expanding_flow(const std::vector<Eigen::Vector3d>& points, const Eigen::Vector3d& c,
                                       double dt) {
  std::vector<FlowVector> flow;
  for (const Eigen::Vector3d& p0 : points) {
    const Eigen::Vector3d p1 = p0 - c * dt;
    flow.push_back({project(p1), project(p1) - project(p0)});
  }
  return flow;
}

std::vector<Eigen::Vector3d> scene(unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> x(-2.0, 2.0), y(-1.0, 1.0), z(2.0, 8.0);
  std::vector<Eigen::Vector3d> pts;
  for (int i = 0; i < 80; ++i) pts.emplace_back(x(rng), y(rng), z(rng));
  return pts;
}

TEST(OpticalFlow, FocusOfExpansionIsTheMotionDirection) {
  const Eigen::Vector3d c(0.1, -0.05, 1.0);  // m/s
  const FoeResult foe = estimate_foe(expanding_flow(scene(1), c, 0.1));
  ASSERT_TRUE(foe.converged) << foe.reason;
  // Eq. 2: FOE = (c_x / c_z, c_y / c_z) in normalised coordinates.
  EXPECT_NEAR(foe.foe_px.x(), kK.fx * 0.1 + kK.cx, 1e-6);
  EXPECT_NEAR(foe.foe_px.y(), kK.fy * -0.05 + kK.cy, 1e-6);
  EXPECT_LT(foe.score, 1e-6);
}

TEST(OpticalFlow, TimeToContactIsDepthOverApproachSpeed) {
  const Eigen::Vector3d c(0.0, 0.0, 0.5);
  const double dt = 0.1;
  const std::vector<Eigen::Vector3d> pts = scene(2);
  const std::vector<FlowVector> flow = expanding_flow(pts, c, dt);
  const FoeResult foe = estimate_foe(flow);
  ASSERT_TRUE(foe.converged);
  for (size_t i = 0; i < pts.size(); ++i) {
    // Eq. 3: tau = D / (dD/dt) = z / c_z, z at the older frame for a finite difference.
    EXPECT_NEAR(time_to_contact_s(flow[i], foe.foe_px, dt), pts[i].z() / c.z(), 1e-6);
  }
}

TEST(OpticalFlow, CollisionTestFlagsOnlyPointsOnThePath) {
  EXPECT_NEAR(closest_approach_m({0.3, 0.0, 2.0}, {0, 0, 1}), 0.3, 1e-12);
  EXPECT_NEAR(closest_approach_m({1.0, 1.0, 0.0}, {1, 1, 0}), 0.0, 1e-12);
  OpticalFlowOptions o;
  o.robot_radius_m = 0.3;
  // An obstacle 1.5 m ahead on the path, background far away and off the path.
  std::vector<Eigen::Vector3d> pts;
  for (int i = 0; i < 5; ++i) pts.emplace_back(-0.09 + 0.05 * i, 0.05 * (i % 2), 1.5);  // none on the FOE itself
  for (int i = 0; i < 20; ++i) pts.emplace_back(-3.0 + 0.3 * i, -1.0, 12.0);
  const std::vector<FlowVector> flow = expanding_flow(pts, {0, 0, 1.0}, 0.1);
  o.min_foe_distance_px = 1.0;
  const CollisionEstimate e = assess_collision(flow, kK, 0.1, 1.0, o);
  ASSERT_TRUE(e.converged) << e.reason;
  EXPECT_EQ(e.risky, 5);
  EXPECT_NEAR(e.min_ttc_s, 1.5, 1e-6);
  EXPECT_LT(e.min_d_m, 0.3);
  EXPECT_GT(e.collision_risk, 0.4f);
  // Stopped robot: no depth from flow.
  EXPECT_FALSE(assess_collision(flow, kK, 0.1, 0.0, o).converged);
  // Sideways flow (all parallel): FOE at infinity, reported, no crash.
  std::vector<FlowVector> side{{{10, 10}, {1, 0}}, {{50, 80}, {1, 0}}, {{90, 20}, {1, 0}}};
  EXPECT_FALSE(estimate_foe(side).converged);
  EXPECT_FALSE(estimate_foe({}).converged);
}

RgbdFrame frame_from(const cv::Mat& rgb, StampNs stamp) {
  RgbdFrame f;
  f.stamp_ns = stamp;
  f.intrinsics = kK;
  f.rgb.assign(rgb.data, rgb.data + rgb.total() * 3);
  f.depth.assign(size_t(kK.width) * kK.height, 2000);
  return f;
}

TEST(OpticalFlow, LucasKanadeOnAZoomedImageFindsTheZoomCentre) {
  cv::Mat noise(480, 640, CV_8UC3);
  cv::randu(noise, 0, 255);
  cv::GaussianBlur(noise, noise, cv::Size(7, 7), 2.0);
  // Frame 0: the centre crop; frame 1: zoomed 4 % about (180, 110) (approaching that point).
  const cv::Mat a = noise(cv::Rect(160, 120, 320, 240)).clone();
  cv::Mat M = cv::getRotationMatrix2D(cv::Point2f(180, 110), 0.0, 1.04), b;
  cv::warpAffine(a, b, M, a.size(), cv::INTER_LINEAR, cv::BORDER_REFLECT);
  OpticalFlowCollision flow;
  EXPECT_FALSE(flow.update(frame_from(a, 1'000'000'000), 0.5, 0.0).converged);  // first frame
  const CollisionEstimate e = flow.update(frame_from(b, 1'100'000'000), 0.5, 0.0);
  ASSERT_TRUE(e.converged) << e.reason;
  EXPECT_NEAR(e.foe_px.x(), 180.0, 3.0);
  EXPECT_NEAR(e.foe_px.y(), 110.0, 3.0);
  EXPECT_GT(e.tracked, 50);
  // Uniform zoom 1.04 in 0.1 s: tau = 1 / (0.04 / 0.1) = 2.6 s (measured in the newer frame).
  EXPECT_NEAR(e.min_ttc_s, 2.6, 0.5);
  RgbdFrame bad = frame_from(b, 1'200'000'000);
  bad.depth.clear();
  EXPECT_FALSE(flow.update(bad, 0.5, 0.0).converged);
}

}  // namespace
}  // namespace cairn::agent
