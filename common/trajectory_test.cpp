#include "common/trajectory.h"

#include <gtest/gtest.h>

#include <fstream>

#include "common/errors.h"

namespace cairn {
namespace {

Trajectory circle(const SE2& offset) {
  Trajectory t;
  for (int i = 0; i < 100; ++i) {
    const double a = i * 0.06;
    t.push_back({StampNs(i) * 100'000'000, offset * SE2(std::cos(a) * 3, std::sin(a) * 3, a + M_PI / 2)});
  }
  return t;
}

TEST(Trajectory, AlignmentRemovesARigidOffsetExactly) {
  const Trajectory ref = circle(SE2());
  const Trajectory est = circle(SE2(5.0, -2.0, 1.0));
  auto stats = trajectory_error(est, ref);
  ASSERT_TRUE(stats);
  EXPECT_EQ(stats->matched, 100);
  EXPECT_LT(stats->ate_rmse_m, 1e-9);
  EXPECT_LT(stats->rpe_trans_mean_m, 1e-9);
  TrajectoryErrorOptions no_align;
  no_align.align = false;
  EXPECT_GT(trajectory_error(est, ref, no_align)->ate_rmse_m, 1.0);
}

TEST(Trajectory, ErrorOfAKnownPerturbation) {
  const Trajectory ref = circle(SE2());
  Trajectory est = ref;
  for (size_t i = 0; i < est.size(); ++i) {
    const double d = (i % 2 ? 0.1 : -0.1);
    est[i].pose = SE2(est[i].pose.x() + d, est[i].pose.y(), est[i].pose.yaw());
  }
  auto stats = trajectory_error(est, ref);
  ASSERT_TRUE(stats);
  EXPECT_NEAR(stats->ate_rmse_m, 0.1, 0.01);
}

TEST(Trajectory, InterpolatesBetweenStampsAndNotOutside) {
  Trajectory t{{0, SE2(0, 0, 0)}, {kNsPerSec, SE2(2, 0, 0)}};
  EXPECT_NEAR(interpolate_pose(t, kNsPerSec / 4)->x(), 0.5, 1e-12);
  EXPECT_FALSE(interpolate_pose(t, -1));
  EXPECT_FALSE(interpolate_pose(t, 2 * kNsPerSec));
}

TEST(Trajectory, CsvRoundTripAndMalformedLineNamed) {
  const std::string path = ::testing::TempDir() + "/traj_test.csv";
  const Trajectory t = circle(SE2());
  ASSERT_TRUE(write_trajectory_csv(path, t));
  const Trajectory back = read_trajectory_csv(path);
  ASSERT_EQ(back.size(), t.size());
  EXPECT_NEAR(back[42].pose.y(), t[42].pose.y(), 1e-6);
  {
    std::ofstream bad(path);
    bad << "stamp_ns,x_m,y_m,yaw_rad\n1,2,3,4\n5,nan,1,1\n";
  }
  try {
    read_trajectory_csv(path);
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find(":3:"), std::string::npos) << e.what();
  }
  EXPECT_THROW(read_trajectory_csv("/nonexistent/traj.csv"), InputError);
}

}  // namespace
}  // namespace cairn
