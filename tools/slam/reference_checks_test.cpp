#include "tools/slam/reference_checks.h"

#include <gtest/gtest.h>

#include <cmath>

#include "common/errors.h"
#include "robot_agent/core/test_util.h"

namespace cairn::slam {
namespace {

using agent::testing::ray_cast;
using Walls = std::vector<agent::testing::Segment>;

// A ring corridor 2 m wide around a 16 x 6 m block, driven twice with 360-beam scans; the second
// lap 0.25 m further on (so its scans are not copies of the first).
struct Ring {
  Walls walls{{{0, 0}, {20, 0}}, {{20, 0}, {20, 10}}, {{20, 10}, {0, 10}}, {{0, 10}, {0, 0}},
              {{2, 2}, {18, 2}}, {{18, 2}, {18, 8}},  {{18, 8}, {2, 8}},   {{2, 8}, {2, 2}}};
  std::vector<SE2> poses;
  std::vector<LaserScan> scans;
  Ring() {
    for (int lap = 0; lap < 2; ++lap) {
      const double shift = 0.25 * lap;
      for (double x = 1 + shift; x < 19; x += 0.5) poses.emplace_back(x, 1, 0);
      for (double y = 1 + shift; y < 9; y += 0.5) poses.emplace_back(19, y, M_PI / 2);
      for (double x = 19 - shift; x > 1; x -= 0.5) poses.emplace_back(x, 9, M_PI);
      for (double y = 9 - shift; y > 1; y -= 0.5) poses.emplace_back(1, y, -M_PI / 2);
    }
    for (const SE2& p : poses) scans.push_back(ray_cast(walls, p, 0));
  }
};

TEST(ReferenceChecks, RevisitConsistencySeesASecondLapDisplacedByTenCentimetres) {
  const Ring ring;
  std::vector<SE2> displaced = ring.poses;
  for (size_t i = displaced.size() / 2; i < displaced.size(); ++i) displaced[i] = SE2(0, 0.1, 0) * displaced[i];
  const RevisitConsistency good = revisit_consistency(ring.scans, ring.poses);
  const RevisitConsistency bad = revisit_consistency(ring.scans, displaced);
  EXPECT_GT(good.points, 10000);
  EXPECT_GT(good.revisit_fraction, 0.9);
  EXPECT_LT(good.mean_nn_m, 0.02);  // half the spacing of the beams' endpoints at most
  EXPECT_GT(bad.mean_nn_m, 2.0 * good.mean_nn_m);
  EXPECT_LT(bad.within_close_fraction, good.within_close_fraction);
}

TEST(ReferenceChecks, ForwardRangeReadsAStretchedTrajectoryFromTheWallAhead) {
  // A corridor 1 m either side, closed 28 m ahead; 0.4 m steps toward the end wall.
  const Walls walls{{{0, -1}, {28, -1}}, {{0, 1}, {28, 1}}, {{28, -1}, {28, 1}}};
  std::vector<SE2> truth, stretched;
  std::vector<LaserScan> scans;
  for (double x = 0; x < 25; x += 0.4) {
    truth.emplace_back(x, 0, 0);
    stretched.emplace_back(1.03 * x, 0, 0);
    scans.push_back(ray_cast(walls, truth.back(), 0));
  }
  const ForwardRange f = forward_range(scans, {truth, stretched});
  EXPECT_GT(f.pairs, 50);
  EXPECT_NEAR(f.ratio[0], 1.0, 1e-4);
  EXPECT_NEAR(f.ratio[1], 1.03, 1e-3);
  EXPECT_NEAR(f.median_difference_m[1], 0.012, 1e-3);
  // Turning in place between two scans: that pair is not used.
  std::vector<SE2> turning = truth;
  turning[10] = SE2(turning[10].x(), 0, 0.2);
  EXPECT_LT(forward_range(scans, {truth, turning}).pairs, f.pairs);
}

TEST(ReferenceChecks, AffineFitRecoversAStretchAlongOneAxis) {
  std::vector<Eigen::Vector2d> est, ref;
  const Eigen::Matrix2d R = Eigen::Rotation2Dd(30.0 * M_PI / 180).toRotationMatrix();
  const Eigen::Matrix2d A = R * Eigen::Vector2d(1.02, 1.0).asDiagonal() * R.transpose();
  for (int i = 0; i < 50; ++i) {
    est.emplace_back(std::cos(i * 0.3) * 10 + i * 0.2, std::sin(i * 0.7) * 8);
    ref.push_back(A * est.back() + Eigen::Vector2d(3, -2));
  }
  const AffineFit fit = affine_fit(est, ref);
  EXPECT_LT(fit.rmse_m, 1e-9);
  EXPECT_NEAR(fit.scale_major, 1.02, 1e-9);
  EXPECT_NEAR(fit.scale_minor, 1.0, 1e-9);
  EXPECT_NEAR(fit.major_axis_deg, 30.0, 1e-6);
}

TEST(ReferenceChecks, MismatchedInputIsRefusedWithTheCounts) {
  const Ring ring;
  const std::vector<SE2> short_poses(ring.poses.begin(), ring.poses.begin() + 5);
  try {
    revisit_consistency(ring.scans, short_poses);
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find(std::to_string(ring.scans.size()) + " scans but 5 poses"), std::string::npos)
        << e.what();
  }
  EXPECT_THROW(forward_range(ring.scans, {short_poses}), InputError);
  EXPECT_THROW(affine_fit({{0, 0}, {1, 0}}, {{0, 0}, {1, 0}}), InputError);
}

}  // namespace
}  // namespace cairn::slam
