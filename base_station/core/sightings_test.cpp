// Robots seeing robots (sightings.h): two robots in a featureless field (no laser returns, so scans
// can never link them) see each other's markers as they pass; the base links them on those
// sightings alone and places the second robot within 0.1 m. A robot seen only while it stands
// still gives no rotation and is refused; a sighting never becomes a fixed landmark.
#include "base_station/core/sightings.h"

#include <gtest/gtest.h>

#include <random>

#include "base_station/core/landmark_test_util.h"
#include "base_station/core/mapper_data.h"
#include "base_station/core/multi_robot_mapper.h"
#include "common/robot_markers.h"

namespace cairn::base {
namespace {

constexpr double kDt = 0.1;

/// A robot's true poses at 10 Hz: a circle of radius 3 m around `center` at 0.5 m/s (or standing).
std::vector<SE2> circle(const Eigen::Vector2d& center, double phase_rad, double speed_mps, int steps) {
  std::vector<SE2> out;
  for (int i = 0; i < steps; ++i) {
    const double a = phase_rad + i * speed_mps * kDt / 3.0;
    out.emplace_back(center + 3.0 * Eigen::Vector2d(std::cos(a), std::sin(a)), a + M_PI / 2);
  }
  return out;
}

/// Odometry with a little seeded drift, featureless scans, and sightings of `other` (true poses at
/// the same stamps) while it is within 6 m and 35 deg of the camera's axis (when `camera` is on).
void simulate(RobotId robot, const std::vector<SE2>& truth, RobotId other, const std::vector<SE2>& other_truth,
              bool camera, uint32_t seed, MultiRobotLog* log) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> n01(0.0, 1.0);
  RobotLogData& r = log->robot_data(robot);
  SE2 odom;
  for (size_t i = 0; i < truth.size(); ++i) {
    if (i > 0) {
      const SE2 d = truth[i - 1].between(truth[i]);
      odom = odom * SE2(d.x() * (1 + 0.01 * n01(rng)), d.y() + 0.002 * n01(rng), d.yaw() + 0.002 * n01(rng));
    }
    const StampNs t = sec_to_ns(10.0 + double(i) * kDt);
    r.odometry.push_back({t, odom, 0, 0});
    r.truth.push_back({t, truth[i]});
    r.scans.push_back(testing::featureless_scan(t));
    const Eigen::Vector2d q = truth[i].inverse() * other_truth[i].translation();
    const double bearing = std::atan2(q.y(), q.x());
    if (!camera || q.norm() > 6.0 || q.norm() < 0.5 || std::abs(bearing) > 35.0 * M_PI / 180.0) continue;
    r.landmarks.push_back(LandmarkObservation{robot_marker_landmark(other), t, q.norm() + 0.03 * n01(rng),
                                              bearing + 0.01 * n01(rng), 0.05, 0.02});
  }
}

void merge(const MultiRobotLog& log, MultiRobotMapper* mapper) {
  const auto k0 = testing::keyframes_of(*log.robot(RobotId(0)), 5);
  const auto k1 = testing::keyframes_of(*log.robot(RobotId(1)), 5);
  for (size_t i = 0; i < std::max(k0.size(), k1.size()); ++i) {
    if (i < k0.size()) mapper->add_keyframe(k0[i]);
    if (i < k1.size()) mapper->add_keyframe(k1[i]);
    if (i % 10 == 9) mapper->optimize();
  }
  mapper->optimize();
}

/// Robot 1's last keyframe's global position against the truth (global = robot 0's start frame).
double last_pose_error_m(const MultiRobotMapper& mapper, const MultiRobotLog& log) {
  const Trajectory t1 = mapper.global_trajectory(RobotId(1));
  const SE2 truth =
      log.robot(RobotId(0))->truth.front().pose.inverse() * log.robot(RobotId(1))->truth[t1.size() * 5 - 5].pose;
  return (t1.back().pose.translation() - truth.translation()).norm();
}

TEST(Sightings, RobotsThatSeeEachOtherPassingLinkAndArePlacedWithinATenthOfAMetre) {
  // Two laps in opposite directions on overlapping circles: they meet head-on twice.
  const int steps = int(2 * M_PI * 3.0 / 0.5 / kDt);
  const auto t0 = circle({4, 4}, -M_PI / 2, 0.5, steps), t1 = circle({7, 4}, M_PI / 2, -0.5, steps);
  MultiRobotLog log;
  simulate(RobotId(0), t0, RobotId(1), t1, true, 1, &log);
  simulate(RobotId(1), t1, RobotId(0), t0, true, 2, &log);
  ASSERT_FALSE(log.robot(RobotId(0))->landmarks.empty());
  ASSERT_FALSE(log.robot(RobotId(1))->landmarks.empty());
  MultiRobotMapper mapper;
  merge(log, &mapper);
  ASSERT_FALSE(mapper.landmark_link_events().empty()) << "no sighting link event";
  ASSERT_TRUE(mapper.linked(RobotId(1))) << mapper.landmark_link_events().back().reason;
  EXPECT_NE(mapper.landmark_link_events().back().reason.find("sightings"), std::string::npos);
  EXPECT_TRUE(mapper.landmarks().empty()) << "a teammate's marker is never a fixed landmark";
  const double err = last_pose_error_m(mapper, log);
  EXPECT_LT(err, 0.1);
  std::printf("[sightings] %s; robot 1's last pose %.3f m off\n", mapper.landmark_link_events().back().reason.c_str(),
              err);
}

TEST(Sightings, ARobotSeenOnlyStandingStillGivesNoRotationAndIsNotLinked) {
  const int steps = int(2 * M_PI * 3.0 / 0.5 / kDt);
  const auto t0 = circle({4, 4}, -M_PI / 2, 0.5, steps), t1 = circle({4, 4}, 0.0, 0.0, steps);  // parked on the circle
  MultiRobotLog log;
  simulate(RobotId(0), t0, RobotId(1), t1, true, 1, &log);
  simulate(RobotId(1), t1, RobotId(0), t0, false, 2, &log);  // its camera sees nothing
  ASSERT_FALSE(log.robot(RobotId(0))->landmarks.empty());
  MultiRobotMapper mapper;
  merge(log, &mapper);
  EXPECT_FALSE(mapper.linked(RobotId(1)));
  ASSERT_FALSE(mapper.landmark_link_events().empty());
  EXPECT_NE(mapper.landmark_link_events().back().reason.find("span"), std::string::npos)
      << mapper.landmark_link_events().back().reason;
}

TEST(Sightings, PositionAtInterpolatesBetweenKeyframesAndWaitsForTheNextOne) {
  MapperData data;
  for (int i = 0; i < 2; ++i) {
    Keyframe kf;
    kf.id = KeyframeId{RobotId(1), i};
    kf.stamp_ns = sec_to_ns(double(i));
    kf.T_local_base = SE2(double(i), 0.0, i * M_PI / 2);
    data.keyframes[kf.id] = kf;
  }
  const auto early = position_at(data, RobotId(1), sec_to_ns(0.25));
  ASSERT_TRUE(early);
  EXPECT_EQ(early->keyframe.seq, 0);
  EXPECT_NEAR(early->point_m.x(), 0.25, 1e-9);
  const auto late = position_at(data, RobotId(1), sec_to_ns(0.75));
  ASSERT_TRUE(late);
  EXPECT_EQ(late->keyframe.seq, 1);
  // Expressed from keyframe 1 (turned 90 deg), the point is still 0.75 m along robot 1's start x.
  const Eigen::Vector2d world = data.keyframes.at(late->keyframe).T_local_base * late->point_m;
  EXPECT_NEAR(world.x(), 0.75, 1e-9);
  EXPECT_NEAR(world.y(), 0.0, 1e-9);
  EXPECT_FALSE(position_at(data, RobotId(1), sec_to_ns(1.5))) << "no keyframe after the stamp yet";
  Keyframe far = data.keyframes.at(KeyframeId{RobotId(1), 1});  // keyframes 2-4 never arrived
  far.id.seq = 5;
  far.stamp_ns = sec_to_ns(5.0);
  data.keyframes[far.id] = far;
  EXPECT_FALSE(position_at(data, RobotId(1), sec_to_ns(3.0))) << "keyframes missing in between";
  EXPECT_FALSE(position_at(data, RobotId(2), sec_to_ns(0.5))) << "unknown robot";
}

TEST(Sightings, InvalidOrSelfSightingsAreDroppedAndCounted) {
  Keyframe kf;
  kf.id = KeyframeId{RobotId(0), 3};
  kf.landmarks = {{robot_marker_landmark(RobotId(1)), 5, 2.0, 0.1, 0.05, 0.02},
                  {robot_marker_landmark(RobotId(0)), 5, 2.0, 0.1, 0.05, 0.02},           // itself
                  {robot_marker_landmark(RobotId(2)), 5, std::nan(""), 0.1, 0.05, 0.02},  // NaN range
                  {LandmarkId(4), 5, 2.0, 0.1, 0.05, 0.02}};                              // a fixed marker
  int invalid = 0;
  const std::vector<Sighting> s = sightings_in(kf, &invalid);
  ASSERT_EQ(s.size(), 1u);
  EXPECT_EQ(s[0].seen, RobotId(1));
  EXPECT_EQ(s[0].observer, kf.id);
  EXPECT_EQ(invalid, 2);
}

}  // namespace
}  // namespace cairn::base
